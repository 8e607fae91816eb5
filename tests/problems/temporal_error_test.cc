// Hand-computed residuals and Jacobian checks of problems/temporal_error.h.
#include "problems/temporal_error.h"

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include <ceres/gradient_checker.h>
#include <ceres/numeric_diff_options.h>
#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "core/rotation.h"
#include "tests/problems/functor_test_util.h"

namespace nrsfm {
namespace {

Eigen::Vector3d AxisAngle(double angle, const Eigen::Vector3d& axis) {
  return angle * axis.normalized();
}

Eigen::Matrix3d R(const Eigen::Vector3d& angle_axis) {
  return AngleAxisToRotation(angle_axis);
}

using testing_util::ExpectGradientCheckPasses;
using testing_util::Random;

TEST(WeightsTemporalError, HandComputedResidualAndGradient) {
  const double l_t[3] = {1.0, 0.25, -0.5};
  const double l_prev[3] = {1.0, 0.5, 0.5};
  std::unique_ptr<ceres::CostFunction> cost(WeightsTemporalError::Create(3, 4.0));
  const double* parameters[2] = {l_t, l_prev};
  double r[3];
  ASSERT_TRUE(cost->Evaluate(parameters, r, nullptr));
  EXPECT_DOUBLE_EQ(r[0], 0.0);
  EXPECT_DOUBLE_EQ(r[1], -1.0);
  EXPECT_DOUBLE_EQ(r[2], -4.0);
  ExpectGradientCheckPasses(*cost, {l_t, l_prev});
}

TEST(RotationTemporalError, HandComputedResidual) {
  const Eigen::Vector3d previous(0.3, -1.2, 0.4);
  // Turned 0.25 rad about z (on the left, in the camera frame).
  const Eigen::Vector3d current = RotationToAngleAxis(
      R(AxisAngle(0.25, Eigen::Vector3d::UnitZ())) * R(previous));
  std::unique_ptr<ceres::CostFunction> cost(RotationTemporalError::Create(3.0));
  const double* parameters[2] = {current.data(), previous.data()};
  double r[3];
  ASSERT_TRUE(cost->Evaluate(parameters, r, nullptr));
  EXPECT_NEAR(r[0], 0.0, 1e-14);
  EXPECT_NEAR(r[1], 0.0, 1e-14);
  EXPECT_NEAR(r[2], 0.75, 1e-14);
  // Equal rotations: zero.
  const double* same[2] = {previous.data(), previous.data()};
  ASSERT_TRUE(cost->Evaluate(same, r, nullptr));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r[i], 0.0, 1e-15);
}

TEST(RotationTemporalError, GradientChecker) {
  std::mt19937 rng(11);
  std::unique_ptr<ceres::CostFunction> cost(RotationTemporalError::Create(0.8));
  for (int trial = 0; trial < 5; ++trial) {
    const std::vector<double> v = Random(6, &rng);
    ExpectGradientCheckPasses(*cost, {v.data(), v.data() + 3});
  }
  // Consecutive frames of a video: ~1e-3 rad apart.
  const Eigen::Vector3d previous(0.3, -1.2, 0.4);
  const Eigen::Vector3d current =
      RotationToAngleAxis(R(Eigen::Vector3d(0, 1e-3, 5e-4)) * R(previous));
  ExpectGradientCheckPasses(*cost, {current.data(), previous.data()});
}

}  // namespace
}  // namespace nrsfm
