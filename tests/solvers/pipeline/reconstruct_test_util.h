// Helpers shared by the end-to-end tests of Reconstruct()
// (reconstruct_test.cc; reconstruct_priors_test.cc: what the prior rule
// decides): seeded random-basis sequences and their e3D, and smooth
// deformations seen under an orbit.
#ifndef NRSFM_TESTS_SOLVERS_PIPELINE_RECONSTRUCT_TEST_UTIL_H_
#define NRSFM_TESTS_SOLVERS_PIPELINE_RECONSTRUCT_TEST_UTIL_H_

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/eval/metrics.h"
#include "core/math/random.h"
#include "core/synthetic/synthetic.h"
#include "tests/synthetic_sequences.h"

namespace nrsfm {
namespace testing_util {

constexpr int kFrames = 200;
constexpr int kPoints = 60;
constexpr int kBases = 3;

inline SyntheticSequence Sequence(double noise, double missing,
                                  std::uint64_t seed = 1, int frames = kFrames,
                                  int points = kPoints) {
  return RandomBasisSequence(frames, points, kBases, noise, missing, seed);
}

inline double E3D(const Model& truth, const Model& estimate) {
  return ComputeE3D(CameraFrameShapes(truth), CameraFrameShapes(estimate));
}

// `count` random modes of P points (standard normal coordinates).
inline std::vector<Eigen::Matrix3Xd> RandomModes(int count, int num_points,
                                                 std::uint64_t seed) {
  Random random(seed, /*stream=*/1);
  std::vector<Eigen::Matrix3Xd> modes(count, Eigen::Matrix3Xd(3, num_points));
  for (Eigen::Matrix3Xd& mode : modes) {
    for (int p = 0; p < num_points; ++p) {
      for (int i = 0; i < 3; ++i) mode(i, p) = random.NormalUnpaired();
    }
  }
  return modes;
}

// F frames of a smooth deformation of `num_modes` random modes of P points:
// the first mode plus 0.3/k sin((0.5 + 0.7 k) φ + k) times mode k, with φ
// one turn over the frames.
inline std::vector<Eigen::Matrix3Xd> SmoothModalShapes(int num_frames,
                                                       int num_points,
                                                       int num_modes,
                                                       std::uint64_t seed) {
  const std::vector<Eigen::Matrix3Xd> modes =
      RandomModes(num_modes, num_points, seed);
  std::vector<Eigen::Matrix3Xd> shapes;
  for (int t = 0; t < num_frames; ++t) {
    const double phase = 2.0 * M_PI * t / num_frames;
    Eigen::Matrix3Xd shape = modes[0];
    for (int k = 1; k < num_modes; ++k) {
      shape += 0.3 / k * std::sin((0.5 + 0.7 * k) * phase + k) * modes[k];
    }
    shapes.push_back(shape);
  }
  return shapes;
}

// The object-frame shapes `shapes` (one per frame) seen under an orbit of
// `degrees` at constant speed, written as the Akhter et al. files are (S +
// Rs), so that the truth is scored in its object frame.
inline void OrbitVideo(const std::vector<Eigen::Matrix3Xd>& shapes,
                       double degrees, ReprojectedSequence* video) {
  GroundTruth source;
  source.source = "S+Rs";
  for (const Eigen::Matrix3Xd& shape : shapes) {
    source.points_in_object.push_back(shape);
    source.points_in_camera.push_back(shape);
    source.rotations.push_back(Eigen::Matrix3d::Identity());
  }
  ReprojectOptions camera_path;
  camera_path.total_rotation_deg = degrees;
  ASSERT_TRUE(GenerateReprojection(source, camera_path, video).ok());
}

// `nrsfm synth --dataset random --frames 100 --points 30 --K 3 --noise
// 0.01 --missing 0.1 --seed 11`: with the data term alone (the rule's old
// branch for tracks explained by K bases) the answer was 497.9 times deeper
// than its image extent, e3D 308. Noisy tracks now get the shape prior (a
// weak one: the start's frames deform independently).
inline SyntheticSequence NoisyRandom(std::uint64_t seed, double noise) {
  return Sequence(noise, 0.1, seed, 100, 30);  // K = kBases = 3
}

}  // namespace testing_util
}  // namespace nrsfm

#endif  // NRSFM_TESTS_SOLVERS_PIPELINE_RECONSTRUCT_TEST_UTIL_H_
