#include "solvers/start/pose_fit.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/LU>

#include "core/math/rotation.h"

namespace nrsfm {
namespace {

TEST(PoseFit, ScaledRotationFromTwoRowsIsExactOnAScaledRotation) {
  const Eigen::Matrix3d r =
      AngleAxisToRotation(Eigen::Vector3d(0.4, -1.1, 0.7));
  Eigen::Matrix3d rotation;
  double scale = 0.0;
  ScaledRotationFromTwoRows(2.5 * r.topRows<2>(), &rotation, &scale);
  EXPECT_NEAR(scale, 2.5, 1e-14);
  EXPECT_LT((rotation - r).norm(), 1e-14);
  // A perturbed block still gives a proper rotation.
  Eigen::Matrix<double, 2, 3> m = r.topRows<2>();
  m(0, 1) += 0.2;
  ScaledRotationFromTwoRows(m, &rotation, &scale);
  EXPECT_LT(
      (rotation * rotation.transpose() - Eigen::Matrix3d::Identity()).norm(),
      1e-14);
  EXPECT_NEAR(rotation.determinant(), 1.0, 1e-14);
}

TEST(PoseFit, WeakPerspectivePoseIsExactOnNoiseFreePoints) {
  const Eigen::Matrix3Xd points = Eigen::Matrix3Xd::Random(3, 20);
  const Eigen::Matrix3d r =
      AngleAxisToRotation(Eigen::Vector3d(-0.3, 0.9, 2.0));
  const Eigen::Matrix2Xd observed = 0.8 * r.topRows<2>() * points;
  Eigen::Matrix3d rotation;
  double scale = 0.0;
  ASSERT_TRUE(FitWeakPerspectivePose(observed, points, 10, &rotation, &scale));
  EXPECT_NEAR(scale, 0.8, 1e-12);
  EXPECT_LT(RotationAngleBetween(rotation, r), 1e-12);

  // Coplanar points do not determine the pose.
  Eigen::Matrix3Xd flat = points;
  flat.row(2).setZero();
  EXPECT_FALSE(FitWeakPerspectivePose(0.8 * r.topRows<2>() * flat, flat, 10,
                                      &rotation, &scale));
}

TEST(PoseFit, RefineRotationConvergesAndNeverIncreasesTheCost) {
  const Eigen::Matrix3Xd points = Eigen::Matrix3Xd::Random(3, 30);
  const Eigen::Matrix3d r =
      AngleAxisToRotation(Eigen::Vector3d(0.5, 0.2, -0.4));
  const Eigen::Matrix2Xd observed = r.topRows<2>() * points;
  // The start, ~5.5° from r.
  Eigen::Matrix3d rotation =
      AngleAxisToRotation(Eigen::Vector3d(0.05, -0.08, 0.03)) * r;
  const double start = PoseCost(observed, points, 1.0, rotation);
  const double one_step = RefineRotation(observed, points, 1.0, 1, &rotation);
  EXPECT_LT(one_step, start);
  const double final_cost =
      RefineRotation(observed, points, 1.0, 20, &rotation);
  EXPECT_LE(final_cost, one_step);
  EXPECT_LT(RotationAngleBetween(rotation, r), 1e-10);
}

}  // namespace
}  // namespace nrsfm
