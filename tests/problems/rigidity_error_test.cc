// Hand-computed residuals and Jacobian checks of problems/rigidity_error.h.
#include "problems/rigidity_error.h"

#include <ceres/gradient_checker.h>
#include <ceres/numeric_diff_options.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "core/math/rotation.h"
#include "tests/problems/functor_test_util.h"
#include "tests/problems/term_test_util.h"

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

TEST(RigidityError, ZeroOnAnExactRigAndHandComputedOtherwise) {
  const Eigen::Vector3d omega_0 =
      AxisAngle(0.3, Eigen::Vector3d(0.2, 0.1, 1.0));
  const Eigen::Vector3d rig = AxisAngle(0.5, Eigen::Vector3d::UnitY());
  Eigen::Vector3d omega_c = RotationToAngleAxis(R(rig) * R(omega_0));
  double scale_c = 0.9;
  double rig_scale = 0.9;
  std::unique_ptr<ceres::CostFunction> cost(RigidityError::Create(2.0));
  const double* parameters[5] = {omega_c.data(), omega_0.data(), rig.data(),
                                 &scale_c, &rig_scale};
  double r[4];
  ASSERT_TRUE(cost->Evaluate(parameters, r, nullptr));
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(r[i], 0.0, 1e-14) << i;

  // Camera c turned 0.1 rad further about y, its scale 0.05 above the rig's:
  // R_tc R_t0ᵀ R_rigᵀ = Ry(0.1) → r = 2 · (0, 0.1, 0, 0.05).
  omega_c = RotationToAngleAxis(R(AxisAngle(0.6, Eigen::Vector3d::UnitY())) *
                                R(omega_0));
  scale_c = 0.95;
  ASSERT_TRUE(cost->Evaluate(parameters, r, nullptr));
  EXPECT_NEAR(r[0], 0.0, 1e-14);
  EXPECT_NEAR(r[1], 0.2, 1e-14);
  EXPECT_NEAR(r[2], 0.0, 1e-14);
  EXPECT_NEAR(r[3], 0.1, 1e-14);

  // A discrepancy on the left of the rig: R_tc = R_rig R_t0 Rx(0.2) gives
  // the angle-axis of R_rig R_t0 Rx(0.2) R_t0ᵀ R_rigᵀ, norm 0.2.
  omega_c = RotationToAngleAxis(R(rig) * R(omega_0) *
                                R(AxisAngle(0.2, Eigen::Vector3d::UnitX())));
  ASSERT_TRUE(cost->Evaluate(parameters, r, nullptr));
  const Eigen::Vector3d expected =
      2.0 * (R(rig) * R(omega_0) * Eigen::Vector3d(0.2, 0, 0));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r[i], expected[i], 1e-14) << i;
}

TEST(RigidityError, GradientChecker) {
  std::mt19937 rng(5);
  std::unique_ptr<ceres::CostFunction> cost(RigidityError::Create(1.7));
  for (int trial = 0; trial < 5; ++trial) {
    const std::vector<double> v = Random(11, &rng);
    ExpectGradientCheckPasses(*cost, {v.data(), v.data() + 3, v.data() + 6,
                                      v.data() + 9, v.data() + 10});
  }
  // Near a consistent rig (discrepancy ~1e-3 rad, the solver's end point).
  const Eigen::Vector3d omega_0(0.4, -0.2, 0.1);
  const Eigen::Vector3d rig(0.0, 0.5, 0.0);
  const Eigen::Vector3d omega_c =
      RotationToAngleAxis(R(rig) * R(omega_0) * R(Eigen::Vector3d(1e-3, 0, 0)));
  const double scale_c = 0.9;
  const double rig_scale = 0.91;
  ExpectGradientCheckPasses(*cost, {omega_c.data(), omega_0.data(), rig.data(),
                                    &scale_c, &rig_scale});
}

// Its row of problems/extra_terms.cc: one block per frame t and camera
// c ≥ 1, and the rig blocks of the cameras c ≥ 1 are free by default.
TEST(RigidityTerm, OneBlockPerFrameAndCameraAfterTheFirst) {
  SyntheticSequence s = testing_util::TermTestShoe(2);  // the shoe has M ≤ 2
  EXPECT_EQ(testing_util::TermBlockCount(kRigidityTerm, s),
            testing_util::kTermFrames * (2 - 1));
  ProblemOptions options;
  options.term_weights[kRigidityTerm] = 1.0;
  Model model = s.truth;
  ProblemBuilder builder(&s.measurements, &model);
  ASSERT_TRUE(builder.AddReprojectionTerms(options).ok());
  ASSERT_TRUE(AddExtraTerms(options, &builder).ok());
  EXPECT_TRUE(
      builder.problem()->HasParameterBlock(builder.RigRotationBlock(1)));
  EXPECT_TRUE(builder.problem()->HasParameterBlock(builder.RigScaleBlock(1)));
  EXPECT_FALSE(
      builder.problem()->IsParameterBlockConstant(builder.RigScaleBlock(1)));
}

}  // namespace
}  // namespace nrsfm
