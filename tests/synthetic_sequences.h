// The tests' maker of random-basis sequences (core/synthetic/synthetic.h):
// F frames, P points, K bases, noise on W, a fraction of missing entries
// and the generator's seed; the other options at their defaults.
#ifndef NRSFM_TESTS_SYNTHETIC_SEQUENCES_H_
#define NRSFM_TESTS_SYNTHETIC_SEQUENCES_H_

#include <gtest/gtest.h>

#include <cstdint>

#include "core/synthetic/synthetic.h"

namespace nrsfm {
namespace testing_util {

inline SyntheticSequence RandomBasisSequence(int frames, int points, int bases,
                                             double noise = 0.0,
                                             double missing = 0.0,
                                             std::uint64_t seed = 1) {
  RandomBasisOptions options;
  options.num_frames = frames;
  options.num_points = points;
  options.num_bases = bases;
  options.noise_stddev = noise;
  options.missing_fraction = missing;
  options.seed = seed;
  SyntheticSequence sequence;
  EXPECT_TRUE(GenerateRandomBasis(options, &sequence).ok());
  return sequence;
}

// The truth of a sequence as GenerateReprojection takes it: the object-frame
// shapes S_t, camera 0's rotations and camera-frame shapes ("S+Rs").
inline GroundTruth ObjectFrameTruth(const SyntheticSequence& sequence) {
  GroundTruth truth;
  truth.source = "S+Rs";
  for (int t = 0; t < sequence.truth.num_frames; ++t) {
    truth.points_in_object.push_back(sequence.truth.ShapeInObject(t));
    truth.rotations.push_back(sequence.truth.Rotation(t, 0));
    truth.points_in_camera.push_back(sequence.truth.ShapeInCamera(t, 0));
  }
  return truth;
}

}  // namespace testing_util
}  // namespace nrsfm

#endif  // NRSFM_TESTS_SYNTHETIC_SEQUENCES_H_
