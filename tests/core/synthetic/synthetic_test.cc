#include "core/synthetic/synthetic.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>

#include "core/math/rotation.h"
#include "core/math/svd.h"
#include "tests/core/synthetic/synthetic_test_util.h"

namespace nrsfm {
namespace {

using testing_util::kDegToRad;
using testing_util::kPi;
using testing_util::MissingFraction;
using testing_util::SameBytes;

// Singular values of W, largest first (W must be complete).
Eigen::VectorXd SingularValues(const Eigen::MatrixXd& w) {
  return ComputeThinSvd(w, SingularVectors::kNone).singular_values;
}

// Largest |W − truth.Project| over the visible entries; also checks that the
// missing entries are NaN.
double MaxProjectionGap(const SyntheticSequence& s) {
  const Measurements& m = s.measurements;
  double gap = 0.0;
  for (int t = 0; t < m.num_frames; ++t) {
    for (int c = 0; c < m.num_cameras; ++c) {
      const Eigen::Matrix2Xd projected = s.truth.Project(t, c);
      for (int p = 0; p < m.num_points; ++p) {
        if (m.visible(m.View(t, c), p)) {
          gap = std::max(gap, (m.Observation(t, c, p) - projected.col(p))
                                  .cwiseAbs()
                                  .maxCoeff());
        } else {
          EXPECT_TRUE(std::isnan(m.W(m.Row(t, c), p)) &&
                      std::isnan(m.W(m.Row(t, c) + 1, p)))
              << "frame " << t << " camera " << c << " point " << p;
        }
      }
    }
  }
  return gap;
}

bool SameTruth(const Model& a, const Model& b) {
  return SameBytes(a.rotations, b.rotations) &&
         SameBytes(a.translations, b.translations) &&
         SameBytes(a.weights, b.weights) && SameBytes(a.basis, b.basis) &&
         SameBytes(a.scales, b.scales) &&
         SameBytes(a.rig_rotations, b.rig_rotations) &&
         SameBytes(a.rig_scales, b.rig_scales);
}

TEST(RandomBasis, SizesTruthAndExactRank3K) {
  RandomBasisOptions options;  // F = 300, P = 50, K = 5, noise-free, complete.
  SyntheticSequence s;
  ASSERT_TRUE(GenerateRandomBasis(options, &s).ok());
  const Measurements& m = s.measurements;
  EXPECT_EQ(m.num_frames, 300);
  EXPECT_EQ(m.num_cameras, 1);
  EXPECT_EQ(m.num_points, 50);
  EXPECT_EQ(m.W.rows(), 600);
  EXPECT_TRUE(m.IsComplete());
  ASSERT_TRUE(m.Validate().ok());
  ASSERT_TRUE(s.truth.Validate().ok());
  EXPECT_EQ(s.truth.num_bases, 5);
  EXPECT_TRUE((s.truth.weights.row(0).array() == 1.0).all());
  EXPECT_TRUE(s.truth.translations.isZero(0.0));
  // Every basis is centred, hence every frame of W.
  EXPECT_LT(s.truth.basis.rowwise().mean().cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT(m.W.rowwise().mean().cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_EQ(MaxProjectionGap(s), 0.0);
  // Basis points come from the unit cube (then shifted by their mean).
  EXPECT_LT(s.truth.basis.cwiseAbs().maxCoeff(), 1.0);

  const Eigen::VectorXd sv = SingularValues(m.W);
  EXPECT_LT(sv(15) / sv(0), 1e-12) << sv.transpose();
  EXPECT_GT(sv(14) / sv(0), 1e-3) << sv.transpose();
}

TEST(RandomBasis, RotationsSpanTheRequestedRange) {
  RandomBasisOptions options;
  SyntheticSequence s;
  ASSERT_TRUE(GenerateRandomBasis(options, &s).ok());
  // Three factors of at most 45° each: R_t is within 135° of the identity,
  // and the sequence turns by a large part of its range.
  double largest_turn = 0.0;
  for (int t = 0; t < options.num_frames; ++t) {
    EXPECT_LE(RotationAngleBetween(s.truth.Rotation(t, 0),
                                   Eigen::Matrix3d::Identity()),
              135.0 * kDegToRad + 1e-12);
    largest_turn = std::max(
        largest_turn,
        RotationAngleBetween(s.truth.Rotation(t, 0), s.truth.Rotation(0, 0)));
  }
  EXPECT_GT(largest_turn, 45.0 * kDegToRad);
  options.max_rotation_deg = 0.0;
  ASSERT_TRUE(GenerateRandomBasis(options, &s).ok());
  EXPECT_TRUE(s.truth.rotations.isZero(0.0));
}

TEST(RandomBasis, DeterministicPerSeed) {
  RandomBasisOptions options;
  options.noise_stddev = 0.01;
  options.missing_fraction = 0.2;
  SyntheticSequence a, b, c;
  ASSERT_TRUE(GenerateRandomBasis(options, &a).ok());
  ASSERT_TRUE(GenerateRandomBasis(options, &b).ok());
  EXPECT_TRUE(SameBytes(a.measurements.W, b.measurements.W));
  EXPECT_TRUE((a.measurements.visible == b.measurements.visible).all());
  EXPECT_TRUE(SameTruth(a.truth, b.truth));
  options.seed = 2;
  ASSERT_TRUE(GenerateRandomBasis(options, &c).ok());
  EXPECT_FALSE(SameBytes(a.measurements.W, c.measurements.W));
  EXPECT_FALSE(SameTruth(a.truth, c.truth));
}

TEST(RandomBasis, NoiseHasTheRequestedStdAndLeavesTheTruthAlone) {
  RandomBasisOptions options;
  SyntheticSequence clean, noisy;
  ASSERT_TRUE(GenerateRandomBasis(options, &clean).ok());
  options.noise_stddev = 0.02;
  ASSERT_TRUE(GenerateRandomBasis(options, &noisy).ok());
  EXPECT_TRUE(SameTruth(clean.truth, noisy.truth));
  const Eigen::ArrayXXd noise =
      (noisy.measurements.W - clean.measurements.W).array();
  const double n = static_cast<double>(noise.size());  // 30000 samples
  const double mean = noise.mean();
  const double stddev = std::sqrt((noise - mean).square().sum() / (n - 1.0));
  // Standard errors: of the mean 0.02 / √n ≈ 1.2e-4, of the std ≈ 0.4 %.
  EXPECT_LT(std::abs(mean), 5e-4);
  EXPECT_NEAR(stddev, 0.02, 0.02 * 0.02);
  // Gaussian: about 68.3 % within one std (binomial std 0.27 %).
  const double within = (noise.abs() < 0.02).cast<double>().mean();
  EXPECT_NEAR(within, 0.6827, 0.01);
}

TEST(RandomBasis, MissingFractionAndMinimumCounts) {
  RandomBasisOptions options;
  options.missing_fraction = 0.3;
  SyntheticSequence s, complete;
  ASSERT_TRUE(GenerateRandomBasis(options, &s).ok());
  const Measurements& m = s.measurements;
  EXPECT_NEAR(MissingFraction(m, 0), 0.3, 1e-3);
  EXPECT_GE(m.VisiblePerView().minCoeff(), 2);
  EXPECT_GE(m.VisiblePerPoint().minCoeff(), 2);
  EXPECT_TRUE(m.Validate().ok());
  EXPECT_EQ(MaxProjectionGap(s), 0.0);
  options.missing_fraction = 0.0;
  ASSERT_TRUE(GenerateRandomBasis(options, &complete).ok());
  EXPECT_TRUE(SameTruth(s.truth, complete.truth));

  // A tiny sequence cannot lose more than the minimum counts allow.
  options.num_frames = 3;
  options.num_points = 3;
  options.missing_fraction = 0.9;
  ASSERT_TRUE(GenerateRandomBasis(options, &s).ok());
  EXPECT_GE(s.measurements.VisiblePerView().minCoeff(), 2);
  EXPECT_GE(s.measurements.VisiblePerPoint().minCoeff(), 2);
}

TEST(RandomBasis, CheckRejectsBadOptions) {
  auto message = [](const RandomBasisOptions& options) {
    SyntheticSequence s;
    const Status status = GenerateRandomBasis(options, &s);
    EXPECT_FALSE(status.ok());
    EXPECT_EQ(status.message(), options.Check().message());
    return status.message();
  };
  RandomBasisOptions o;
  EXPECT_TRUE(o.Check().ok());
  o.num_frames = 1;
  EXPECT_EQ(message(o), "RandomBasisOptions: num_frames must be >= 2, got 1");
  o = RandomBasisOptions();
  o.num_bases = 0;
  EXPECT_EQ(message(o), "RandomBasisOptions: num_bases must be >= 1, got 0");
  o = RandomBasisOptions();
  o.num_points = 0;
  EXPECT_EQ(message(o), "RandomBasisOptions: num_points must be >= 1, got 0");
  o = RandomBasisOptions();
  o.missing_fraction = 1.0;
  EXPECT_EQ(message(o),
            "RandomBasisOptions: missing_fraction must be in [0, 1), got 1");
  o = RandomBasisOptions();
  o.noise_stddev = -0.5;
  EXPECT_EQ(
      message(o),
      "RandomBasisOptions: noise_stddev must be finite and >= 0, got -0.5");
  o = RandomBasisOptions();
  o.deformation = NAN;
  EXPECT_NE(message(o).find("deformation must be finite"), std::string::npos);
  o = RandomBasisOptions();
  o.max_rotation_deg = 400.0;
  EXPECT_EQ(
      message(o),
      "RandomBasisOptions: max_rotation_deg must be in [0, 360], got 400");
}

// The documented surface |x/0.5|^4 + |y/0.4|^4 + |z/0.3|^4 = 1 (e = 0.5),
// minus 1, at point + centre.
double SurfaceResidual(const Eigen::Vector3d& point,
                       const Eigen::Vector3d& centre) {
  const Eigen::Array3d u =
      (point + centre).array() / Eigen::Array3d(0.5, 0.4, 0.3);
  return u.abs().pow(4.0).sum() - 1.0;
}

// The basis is centred, so the rest shape sits on the superquadric shifted by
// an unknown centre: find it by Gauss-Newton on the surface equation.
Eigen::Vector3d FitSuperquadricCentre(const Eigen::Matrix3Xd& rest) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int iteration = 0; iteration < 30; ++iteration) {
    Eigen::MatrixXd jacobian(rest.cols(), 3);
    Eigen::VectorXd residual(rest.cols());
    for (Eigen::Index p = 0; p < rest.cols(); ++p) {
      residual(p) = SurfaceResidual(rest.col(p), centre);
      const Eigen::Array3d axes(0.5, 0.4, 0.3);
      const Eigen::Array3d u = (rest.col(p) + centre).array() / axes;
      jacobian.row(p) =
          (4.0 * u.abs().pow(3.0) * u.sign() / axes).matrix().transpose();
    }
    centre -= jacobian.colPivHouseholderQr().solve(residual);
  }
  return centre;
}

TEST(Superquadric, PointsOnTheSurfaceAndOneModePerOctant) {
  SuperquadricOptions options;
  SyntheticSequence s;
  ASSERT_TRUE(GenerateSuperquadric(options, &s).ok());
  const Model& truth = s.truth;
  ASSERT_TRUE(truth.Validate().ok());
  EXPECT_EQ(truth.num_bases, 4);
  EXPECT_EQ(s.measurements.num_points, 200);
  EXPECT_TRUE((truth.weights.row(0).array() == 1.0).all());
  EXPECT_LE(truth.weights.bottomRows(3).cwiseAbs().maxCoeff(), 0.5);
  EXPECT_EQ(MaxProjectionGap(s), 0.0);

  const Eigen::Matrix3Xd rest = truth.BasisShape(0);
  const Eigen::Vector3d centre = FitSuperquadricCentre(rest);
  EXPECT_LT(centre.norm(), 0.1);
  for (int p = 0; p < rest.cols(); ++p) {
    EXPECT_LT(std::abs(SurfaceResidual(rest.col(p), centre)), 1e-10)
        << "point " << p;
  }
  // Mode o moves only the points of its octant (+,+,+), (−,−,+), (+,−,−);
  // after centring every other point has the same displacement.
  const double octants[3][3] = {{1, 1, 1}, {-1, -1, 1}, {1, -1, -1}};
  for (int o = 0; o < 3; ++o) {
    const Eigen::Matrix3Xd mode = truth.BasisShape(o + 1);
    int inside = 0, moved = 0;
    Eigen::Vector3d outside_value = Eigen::Vector3d::Constant(NAN);
    for (int p = 0; p < rest.cols(); ++p) {
      const Eigen::Vector3d x = rest.col(p) + centre;
      const bool in = x(0) * octants[o][0] > 0 && x(1) * octants[o][1] > 0 &&
                      x(2) * octants[o][2] > 0;
      if (!in) {
        if (std::isnan(outside_value(0))) outside_value = mode.col(p);
        EXPECT_LT((mode.col(p) - outside_value).norm(), 1e-15)
            << "mode " << o << " point " << p;
      } else {
        ++inside;
      }
    }
    for (int p = 0; p < rest.cols(); ++p) {
      if ((mode.col(p) - outside_value).norm() > 1e-3) ++moved;
    }
    EXPECT_GT(inside, 10) << "mode " << o;
    EXPECT_GT(moved, inside / 2) << "mode " << o;
  }
  // Exact K = 4 model: noise-free W has rank 12.
  const Eigen::VectorXd sv = SingularValues(s.measurements.W);
  EXPECT_LT(sv(12) / sv(0), 1e-12) << sv.head(14).transpose();
  EXPECT_GT(sv(11) / sv(0), 1e-4) << sv.head(14).transpose();
}

TEST(Superquadric, SharesTheRandomBasisRotationsAndIsDeterministic) {
  SuperquadricOptions options;
  SyntheticSequence a, b;
  ASSERT_TRUE(GenerateSuperquadric(options, &a).ok());
  ASSERT_TRUE(GenerateSuperquadric(options, &b).ok());
  EXPECT_TRUE(SameBytes(a.measurements.W, b.measurements.W));
  EXPECT_TRUE(SameTruth(a.truth, b.truth));
  SyntheticSequence random_basis;
  ASSERT_TRUE(GenerateRandomBasis(RandomBasisOptions(), &random_basis).ok());
  EXPECT_TRUE(SameBytes(a.truth.rotations, random_basis.truth.rotations));
  options.seed = 9;
  options.missing_fraction = 0.1;
  options.noise_stddev = 0.001;
  ASSERT_TRUE(GenerateSuperquadric(options, &b).ok());
  EXPECT_FALSE(SameTruth(a.truth, b.truth));
  EXPECT_NEAR(MissingFraction(b.measurements, 0), 0.1, 1e-3);
  EXPECT_LT(MaxProjectionGap(b), 0.001 * 6);
}

TEST(Superquadric, CheckRejectsBadOptions) {
  SuperquadricOptions o;
  EXPECT_TRUE(o.Check().ok());
  o.num_points = 0;
  SyntheticSequence s;
  const Status status = GenerateSuperquadric(o, &s);
  EXPECT_FALSE(status.ok());
  EXPECT_EQ(status.message(),
            "SuperquadricOptions: num_points must be >= 1, got 0");
  o = SuperquadricOptions();
  o.missing_fraction = -0.1;
  EXPECT_EQ(
      o.Check().message(),
      "SuperquadricOptions: missing_fraction must be in [0, 1), got -0.1");
}

TEST(Shoe, TwoCameraRigSelfOcclusionAndTruth) {
  ShoeOptions options;  // F = 500, P = 110, M = 2, baseline 30°.
  SyntheticSequence s;
  ASSERT_TRUE(GenerateShoe(options, &s).ok());
  const Measurements& m = s.measurements;
  const Model& truth = s.truth;
  ASSERT_TRUE(m.Validate().ok());
  ASSERT_TRUE(truth.Validate().ok());
  EXPECT_EQ(m.num_frames, 500);
  EXPECT_EQ(m.num_cameras, 2);
  EXPECT_EQ(m.num_points, 110);
  EXPECT_EQ(m.W.rows(), 2000);
  EXPECT_EQ(truth.num_bases, 4);
  EXPECT_TRUE((truth.weights.row(0).array() == 1.0).all());
  EXPECT_LT(MaxProjectionGap(s), 1e-15);

  // Rig: R_t1 R_t0ᵀ = Ry(30°) and s_t1 = 0.9 in every frame, as stored.
  const Eigen::Matrix3d rig =
      AngleAxisToRotation(Eigen::Vector3d(0, kPi / 6, 0));
  EXPECT_LT(
      (truth.rig_rotations.col(0) - Eigen::Vector3d(0, kPi / 6, 0)).norm(),
      1e-15);
  EXPECT_EQ(truth.rig_scales(0), 0.9);
  double rig_error = 0.0;
  for (int t = 0; t < m.num_frames; ++t) {
    rig_error = std::max(
        rig_error,
        RotationAngleBetween(
            truth.Rotation(t, 1) * truth.Rotation(t, 0).transpose(), rig));
    EXPECT_EQ(truth.scales(truth.View(t, 0)), 1.0);
    EXPECT_EQ(truth.scales(truth.View(t, 1)), 0.9);
  }
  EXPECT_LT(rig_error, 1e-12);

  // Self-occlusion: 10–20 % missing per camera, minimum counts kept.
  for (int c = 0; c < 2; ++c) {
    const double missing = MissingFraction(m, c);
    EXPECT_GT(missing, 0.10) << "camera " << c;
    EXPECT_LT(missing, 0.20) << "camera " << c;
  }
  EXPECT_GE(m.VisiblePerView().minCoeff(), 4);
  EXPECT_GE(m.VisiblePerPoint().minCoeff(), 1);

  // The toe bend is local: the heel half has one common displacement.
  const Eigen::Matrix3Xd rest = truth.BasisShape(0);
  const Eigen::Matrix3Xd toe = truth.BasisShape(1);
  int heel_points = 0;
  for (int p = 0; p < m.num_points; ++p) {
    if (rest(0, p) < -0.1) {
      EXPECT_LT((toe.col(p) - toe.col(0)).norm(), 1e-15) << "point " << p;
      ++heel_points;
    }
  }
  EXPECT_GT(heel_points, 20);
  ASSERT_LT(rest(0, 0), -0.1);  // point 0 is on the heel end of an edge
  // Large rotations: the yaw spans most of the documented 120°.
  double largest = 0.0;
  for (int t = 0; t < m.num_frames; ++t) {
    largest = std::max(largest, RotationAngleBetween(truth.Rotation(t, 0),
                                                     truth.Rotation(0, 0)));
  }
  EXPECT_GT(largest, 60.0 * kDegToRad);
}

TEST(Shoe, ExactLowRankWithoutOcclusion) {
  ShoeOptions options;
  options.self_occlusion = false;
  SyntheticSequence s;
  ASSERT_TRUE(GenerateShoe(options, &s).ok());
  EXPECT_TRUE(s.measurements.IsComplete());
  // Rank 3K + 1 = 13: the non-zero translations add one column of ones.
  const Eigen::VectorXd sv = SingularValues(s.measurements.W);
  EXPECT_LT(sv(13) / sv(0), 1e-12) << sv.head(15).transpose();
  EXPECT_GT(sv(12) / sv(0), 1e-6) << sv.head(15).transpose();
}

TEST(Shoe, MonocularDeterministicAndNoisy) {
  ShoeOptions options;
  options.num_cameras = 1;
  options.noise_stddev = 0.002;
  SyntheticSequence a, b;
  ASSERT_TRUE(GenerateShoe(options, &a).ok());
  ASSERT_TRUE(GenerateShoe(options, &b).ok());
  EXPECT_EQ(a.measurements.num_cameras, 1);
  EXPECT_EQ(a.truth.rig_rotations.cols(), 0);
  EXPECT_TRUE(SameBytes(a.measurements.W, b.measurements.W));
  EXPECT_TRUE(SameTruth(a.truth, b.truth));
  const double missing = MissingFraction(a.measurements, 0);
  EXPECT_GT(missing, 0.10);
  EXPECT_LT(missing, 0.20);
  options.seed = 5;
  ASSERT_TRUE(GenerateShoe(options, &b).ok());
  EXPECT_FALSE(SameTruth(a.truth, b.truth));
  // The noise is the only difference to the projection of the truth.
  double sum_squared = 0.0;
  int count = 0;
  const Measurements& m = a.measurements;
  for (int t = 0; t < m.num_frames; ++t) {
    const Eigen::Matrix2Xd projected = a.truth.Project(t, 0);
    for (int p = 0; p < m.num_points; ++p) {
      if (!m.visible(t, p)) continue;
      sum_squared += (m.Observation(t, 0, p) - projected.col(p)).squaredNorm();
      count += 2;
    }
  }
  EXPECT_NEAR(std::sqrt(sum_squared / count), 0.002, 0.002 * 0.02);
}

TEST(Shoe, CheckRejectsBadOptions) {
  ShoeOptions o;
  EXPECT_TRUE(o.Check().ok());
  o.num_cameras = 3;
  SyntheticSequence s;
  const Status status = GenerateShoe(o, &s);
  EXPECT_FALSE(status.ok());
  EXPECT_EQ(status.message(),
            "ShoeOptions: num_cameras must be in [1, 2], got 3");
  o = ShoeOptions();
  o.num_points = 5;
  EXPECT_EQ(o.Check().message(),
            "ShoeOptions: num_points must be >= 10, got 5");
  o = ShoeOptions();
  o.camera_baseline_deg = 120.0;
  EXPECT_EQ(o.Check().message(),
            "ShoeOptions: camera_baseline_deg must be in [-90, 90], got 120");
  o = ShoeOptions();
  o.num_frames = 0;
  EXPECT_EQ(o.Check().message(), "ShoeOptions: num_frames must be >= 2, got 0");
}
}  // namespace
}  // namespace nrsfm
