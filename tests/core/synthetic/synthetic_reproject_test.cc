// core/synthetic/synthetic.h: real 3-D ground truth re-projected under a
// chosen camera path (GenerateReprojection,
// core/synthetic/synthetic_reproject.cc).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>

#include "core/math/rotation.h"
#include "core/synthetic/synthetic.h"
#include "tests/core/synthetic/synthetic_test_util.h"

namespace nrsfm {
namespace {

using testing_util::kDegToRad;
using testing_util::MissingFraction;
using testing_util::SameBytes;

// A source for the re-projection tests: the random-basis sequence's truth
// as camera-frame points (no object frame, like P3_gt), or as an object
// frame with its rotations (like S + Rs).
GroundTruth ReprojectSource(bool object_frame) {
  RandomBasisOptions options;
  options.num_frames = 60;
  options.num_points = 30;
  SyntheticSequence s;
  EXPECT_TRUE(GenerateRandomBasis(options, &s).ok());
  GroundTruth source;
  source.source = object_frame ? "S+Rs" : "P3_gt";
  for (int t = 0; t < options.num_frames; ++t) {
    source.points_in_camera.push_back(s.truth.ShapeInCamera(t, 0));
    if (object_frame) {
      source.points_in_object.push_back(s.truth.ShapeInObject(t));
      source.rotations.push_back(s.truth.Rotation(t, 0));
    }
  }
  return source;
}

double AngleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return RotationToAngleAxis(a * b.transpose()).norm() / kDegToRad;
}

TEST(Reproject, CameraPathOfEachProfileAndExactProjections) {
  const GroundTruth source = ReprojectSource(/*object_frame=*/true);
  const int f = source.NumFrames();
  for (SpeedProfile profile : {SpeedProfile::kConstant, SpeedProfile::kRamp,
                               SpeedProfile::kStopAndGo}) {
    SCOPED_TRACE(SpeedProfileName(profile));
    ReprojectOptions options;
    options.total_rotation_deg = 60.0;
    options.profile = profile;
    ReprojectedSequence s;
    ASSERT_TRUE(GenerateReprojection(source, options, &s).ok());
    ASSERT_TRUE(s.measurements.Validate().ok());
    EXPECT_TRUE(s.truth.HasObjectFrame());
    EXPECT_EQ(s.truth.source, "S+Rs");
    // The first camera is the source's; the last has turned Θ about the
    // image's vertical (the axis in R_0's camera frame).
    EXPECT_LT(AngleDeg(s.truth.rotations[0], source.rotations[0]), 1e-12);
    const Eigen::Matrix3d turn =
        s.truth.rotations[f - 1] * source.rotations[0].transpose();
    const Eigen::Vector3d axis_angle = RotationToAngleAxis(turn);
    EXPECT_NEAR(axis_angle.norm() / kDegToRad, 60.0, 1e-9);
    EXPECT_NEAR(std::abs(axis_angle.normalized().y()), 1.0, 1e-12);
    // θ at mid-sequence: constant ½ Θ; ramp ¼ Θ at τ = ½; stop-and-go ½ Θ at
    // τ = ½ (half the moving segments are done). F = 60: τ = 29.5 / 59 is not
    // a frame, so compare frames 0 … F − 1 with the profile's formula.
    for (int t = 0; t < f; ++t) {
      const double tau = static_cast<double>(t) / (f - 1);
      double fraction = tau;
      if (profile == SpeedProfile::kRamp) fraction = tau * tau;
      if (profile == SpeedProfile::kStopAndGo) {
        double moving = 0.0;
        for (int segment = 0; segment < 8; segment += 2) {
          moving += std::clamp(tau - segment / 8.0, 0.0, 1.0 / 8.0);
        }
        fraction = moving / 0.5;
      }
      EXPECT_NEAR(AngleDeg(s.truth.rotations[t], source.rotations[0]),
                  60.0 * fraction, 1e-9)
          << "frame " << t;
      // The object frame is the source's, unchanged; W = Π R_t S_t exactly.
      EXPECT_EQ(s.truth.points_in_object[t], source.points_in_object[t]);
      const Eigen::Matrix2Xd projected =
          (s.truth.rotations[t] * s.truth.points_in_object[t]).topRows<2>();
      EXPECT_LT((s.measurements.W.middleRows<2>(2 * t) - projected)
                    .cwiseAbs()
                    .maxCoeff(),
                1e-12);
    }
  }
}

TEST(Reproject, CameraFrameSourceNoiseMissingAndOcclusion) {
  const GroundTruth source = ReprojectSource(/*object_frame=*/false);
  ReprojectOptions options;
  ReprojectedSequence clean;
  ASSERT_TRUE(GenerateReprojection(source, options, &clean).ok());
  // Without an object frame the source's camera frame is the object frame
  // and R_0 = I.
  EXPECT_LT(AngleDeg(clean.truth.rotations[0], Eigen::Matrix3d::Identity()),
            1e-12);
  EXPECT_EQ(clean.truth.points_in_object[5], source.points_in_camera[5]);
  // The image size: the largest side of a frame's bounding box.
  double size = 0.0;
  for (int t = 0; t < source.NumFrames(); ++t) {
    const Eigen::Matrix2Xd uv = clean.truth.points_in_camera[t].topRows<2>();
    size = std::max(
        size, (uv.rowwise().maxCoeff() - uv.rowwise().minCoeff()).maxCoeff());
  }
  EXPECT_DOUBLE_EQ(clean.image_size, size);
  EXPECT_EQ(clean.noise_stddev, 0.0);

  options.noise_fraction = 0.02;
  options.missing_fraction = 0.3;
  ReprojectedSequence noisy;
  ASSERT_TRUE(GenerateReprojection(source, options, &noisy).ok());
  EXPECT_DOUBLE_EQ(noisy.noise_stddev, 0.02 * size);
  const Measurements& m = noisy.measurements;
  EXPECT_NEAR(MissingFraction(m, 0), 0.3, 1e-3);
  EXPECT_GE(m.VisiblePerView().minCoeff(), 2);
  EXPECT_GE(m.VisiblePerPoint().minCoeff(), 2);
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  for (int t = 0; t < m.num_frames; ++t) {
    for (int p = 0; p < m.num_points; ++p) {
      if (!m.visible(t, p)) {
        EXPECT_TRUE(std::isnan(m.W(2 * t, p)));
        continue;
      }
      for (int i = 0; i < 2; ++i) {
        const double e = m.W(2 * t + i, p) - clean.measurements.W(2 * t + i, p);
        sum += e;
        sum2 += e * e;
        ++n;
      }
    }
  }
  // ~2500 samples: the std within 5 % (its standard error is ~1.4 %).
  EXPECT_NEAR(std::sqrt(sum2 / n - (sum / n) * (sum / n)), noisy.noise_stddev,
              0.05 * noisy.noise_stddev);

  // Self-occlusion: hidden entries have a nearer point within the radius in
  // the image; every point and frame keeps at least 2 entries.
  options = ReprojectOptions();
  options.occlusion_radius = 0.1;
  ReprojectedSequence occluded;
  ASSERT_TRUE(GenerateReprojection(source, options, &occluded).ok());
  const Measurements& o = occluded.measurements;
  EXPECT_GT(MissingFraction(o, 0), 0.05);
  EXPECT_GE(o.VisiblePerView().minCoeff(), 2);
  EXPECT_GE(o.VisiblePerPoint().minCoeff(), 2);
  const double radius = 0.1 * occluded.image_size;
  for (int t = 0; t < o.num_frames; ++t) {
    const Eigen::Matrix3Xd& x = occluded.truth.points_in_camera[t];
    for (int p = 0; p < o.num_points; ++p) {
      bool has_occluder = false;
      for (int q = 0; q < o.num_points; ++q) {
        has_occluder |=
            q != p &&
            (x.col(q).head<2>() - x.col(p).head<2>()).norm() < radius &&
            x(2, p) - x(2, q) >= radius;
      }
      if (!has_occluder) {
        EXPECT_TRUE(o.visible(t, p)) << "frame " << t << " point " << p;
      }
    }
  }

  // Deterministic for a seed; another seed changes only noise and removals.
  options = ReprojectOptions();
  options.noise_fraction = 0.01;
  options.missing_fraction = 0.2;
  ReprojectedSequence a, b, c;
  ASSERT_TRUE(GenerateReprojection(source, options, &a).ok());
  ASSERT_TRUE(GenerateReprojection(source, options, &b).ok());
  options.seed = 2;
  ASSERT_TRUE(GenerateReprojection(source, options, &c).ok());
  EXPECT_TRUE(SameBytes(a.measurements.W, b.measurements.W));
  EXPECT_FALSE((a.measurements.visible == c.measurements.visible).all());
  EXPECT_EQ(a.truth.rotations[7], c.truth.rotations[7]);
}

TEST(Reproject, RejectsBadOptionsAndSources) {
  const GroundTruth source = ReprojectSource(false);
  auto message = [&source](const ReprojectOptions& options) {
    ReprojectedSequence s;
    const Status status = GenerateReprojection(source, options, &s);
    EXPECT_FALSE(status.ok());
    return status.message();
  };
  ReprojectOptions o;
  o.total_rotation_deg = 0.0;
  EXPECT_EQ(message(o),
            "ReprojectOptions: total_rotation_deg must be > 0 (without "
            "rotation the depth "
            "is unobservable)");
  o = ReprojectOptions();
  o.axis.setZero();
  EXPECT_EQ(message(o),
            "ReprojectOptions: axis must be a finite, non-zero direction");
  o = ReprojectOptions();
  o.noise_fraction = -0.1;
  EXPECT_NE(message(o).find("noise_fraction"), std::string::npos);
  o = ReprojectOptions();
  o.missing_fraction = 1.0;
  EXPECT_NE(message(o).find("missing_fraction"), std::string::npos);
  SpeedProfile profile;
  const Status bad = ParseSpeedProfile("jerky", &profile);
  EXPECT_NE(bad.message().find("constant, ramp, stopgo"), std::string::npos)
      << bad.message();

  GroundTruth one_frame = source;
  one_frame.points_in_camera.resize(1);
  one_frame.source = "X";
  ReprojectedSequence s;
  const Status status = GenerateReprojection(one_frame, ReprojectOptions(), &s);
  EXPECT_EQ(status.message(),
            "re-projection: the source 'X' has F = 1, P = 30; needs at least 2 "
            "frames "
            "and 1 point");
}

}  // namespace
}  // namespace nrsfm