#include "solvers/start/metric_upgrade.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <random>

#include "core/math/rotation.h"

namespace nrsfm {
namespace {

Eigen::Vector3d RandomVector(std::mt19937_64* engine) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  return Eigen::Vector3d(uniform(*engine), uniform(*engine), uniform(*engine));
}

TEST(MetricUpgrade, RecoversTheGaugeOfScaledRotations) {
  std::mt19937_64 engine(3);
  const Eigen::Matrix3d g_true =
      Eigen::Matrix3d::Identity() + 0.4 * Eigen::Matrix3d::Random();
  const int n = 40;
  Eigen::MatrixX3d blocks(2 * n, 3);
  for (int i = 0; i < n; ++i) {
    const Eigen::Matrix3d r = AngleAxisToRotation(1.5 * RandomVector(&engine));
    const double scale = 0.5 + 0.1 * i;
    blocks.middleRows<2>(2 * i) = scale * r.topRows<2>() * g_true.inverse();
  }
  MetricUpgrade upgrade;
  ASSERT_TRUE(SolveMetricUpgrade(blocks, &upgrade).ok());
  EXPECT_FALSE(upgrade.was_indefinite);
  EXPECT_GT(upgrade.conditioning, 1e-3);
  // H ∝ G Gᵀ of the truth; every upgraded block has orthogonal rows of
  // equal norm.
  const Eigen::Matrix3d h_true = g_true * g_true.transpose();
  EXPECT_LT((upgrade.h / upgrade.h.norm() - h_true / h_true.norm()).norm(),
            1e-10);
  EXPECT_LT((upgrade.g * upgrade.g.transpose() - upgrade.h).norm(), 1e-10);
  for (int i = 0; i < n; ++i) {
    const Eigen::Matrix<double, 2, 3> m =
        blocks.middleRows<2>(2 * i) * upgrade.g;
    EXPECT_NEAR(m.row(0).dot(m.row(1)) / m.squaredNorm(), 0.0, 1e-10);
    EXPECT_NEAR(
        (m.row(0).squaredNorm() - m.row(1).squaredNorm()) / m.squaredNorm(),
        0.0, 1e-10);
  }
}

TEST(MetricUpgrade, NoRotationIsAnError) {
  const Eigen::Matrix3d r =
      AngleAxisToRotation(Eigen::Vector3d(0.2, 0.1, -0.3));
  Eigen::MatrixX3d blocks(2 * 10, 3);
  for (int i = 0; i < 10; ++i)
    blocks.middleRows<2>(2 * i) = (1.0 + i) * r.topRows<2>();
  MetricUpgrade upgrade;
  const Status status = SolveMetricUpgrade(blocks, &upgrade);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("rotation"), std::string::npos)
      << status.message();
  EXPECT_LT(upgrade.conditioning, kMinMetricConditioning);
}

TEST(MetricUpgrade, IndefiniteMetricIsClampedToPositiveDefinite) {
  // Blocks that are not scaled rotations at all: the least-squares H is
  // often indefinite. Whenever it is, the returned H must be positive
  // definite with eigenvalues at least kMinEigenvalueFraction of the largest.
  std::mt19937_64 engine(11);
  int indefinite = 0;
  for (int trial = 0; trial < 30; ++trial) {
    Eigen::MatrixX3d blocks(2 * 12, 3);
    for (int i = 0; i < 24; ++i)
      blocks.row(i) = RandomVector(&engine).transpose();
    MetricUpgrade upgrade;
    if (!SolveMetricUpgrade(blocks, &upgrade).ok()) continue;
    const Eigen::Vector3d values =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(upgrade.h).eigenvalues();
    EXPECT_GE(values.minCoeff(),
              (1.0 - 1e-9) * kMinEigenvalueFraction * values.maxCoeff());
    EXPECT_TRUE(upgrade.g.allFinite());
    if (upgrade.was_indefinite) ++indefinite;
  }
  EXPECT_GT(indefinite, 0);
}

TEST(MetricUpgrade, RankBelowThreeMeansNoRotation) {
  EXPECT_TRUE(CheckRotationObservable(Eigen::Vector3d(3.0, 2.0, 0.1)).ok());
  const Status status =
      CheckRotationObservable(Eigen::Vector3d(3.0, 2.0, 1e-9));
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("no rotation"), std::string::npos);
  EXPECT_FALSE(CheckRotationObservable(Eigen::Vector2d(3.0, 2.0)).ok());
}

}  // namespace
}  // namespace nrsfm
