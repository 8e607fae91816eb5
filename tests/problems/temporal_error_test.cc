// Hand-computed residuals and Jacobian checks of problems/temporal_error.h.
#include "problems/temporal_error.h"

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
#include "tests/problems/jacobian_product_test_util.h"
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

TEST(WeightsTemporalError, HandComputedResidualAndGradient) {
  const double l_t[3] = {1.0, 0.25, -0.5};
  const double l_prev[3] = {1.0, 0.5, 0.5};
  std::unique_ptr<ceres::CostFunction> cost(
      WeightsTemporalError::Create(3, 4.0));
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

TEST(RotationAccelerationError, ZeroAtConstantAngularVelocityAndHandComputed) {
  // A camera turning 0.1 rad per frame about a fixed axis: zero.
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, 2.0, -0.5).normalized();
  const Eigen::Vector3d start(0.3, -1.2, 0.4);
  const Eigen::Matrix3d step = R(AxisAngle(0.1, axis));
  const Eigen::Vector3d w0 = start;
  const Eigen::Vector3d w1 = RotationToAngleAxis(step * R(w0));
  const Eigen::Vector3d w2 = RotationToAngleAxis(step * R(w1));
  std::unique_ptr<ceres::CostFunction> cost(
      RotationAccelerationError::Create(2.0));
  double r[3];
  const double* steady[3] = {w2.data(), w1.data(), w0.data()};
  ASSERT_TRUE(cost->Evaluate(steady, r, nullptr));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r[i], 0.0, 1e-14);
  // Second step 0.3 rad about z after 0.1 rad about z: 2 · (0.3 − 0.1) on z.
  const Eigen::Vector3d v1 =
      RotationToAngleAxis(R(AxisAngle(0.1, Eigen::Vector3d::UnitZ())) * R(w0));
  const Eigen::Vector3d v2 =
      RotationToAngleAxis(R(AxisAngle(0.3, Eigen::Vector3d::UnitZ())) * R(v1));
  const double* turning[3] = {v2.data(), v1.data(), w0.data()};
  ASSERT_TRUE(cost->Evaluate(turning, r, nullptr));
  EXPECT_NEAR(r[0], 0.0, 1e-14);
  EXPECT_NEAR(r[1], 0.0, 1e-14);
  EXPECT_NEAR(r[2], 0.4, 1e-14);
}

TEST(RotationAccelerationError, GradientChecker) {
  std::mt19937 rng(12);
  std::unique_ptr<ceres::CostFunction> cost(
      RotationAccelerationError::Create(1.5));
  for (int trial = 0; trial < 5; ++trial) {
    const std::vector<double> v = Random(9, &rng);
    ExpectGradientCheckPasses(*cost, {v.data(), v.data() + 3, v.data() + 6});
  }
  // Video-like: all three ~1e-3 rad apart.
  const Eigen::Vector3d w0(0.3, -1.2, 0.4);
  const Eigen::Vector3d w1 =
      RotationToAngleAxis(R(Eigen::Vector3d(0, 1e-3, 5e-4)) * R(w0));
  const Eigen::Vector3d w2 =
      RotationToAngleAxis(R(Eigen::Vector3d(2e-4, 1e-3, 0)) * R(w1));
  ExpectGradientCheckPasses(*cost, {w2.data(), w1.data(), w0.data()});
}

TEST(ShapeTemporalError, HandComputedResidualAndGradient) {
  // K = 2; point p of basis 1 = (1, 2, 3), of basis 2 = (0, −1, 4).
  const double basis[6] = {1.0, 2.0, 3.0, 0.0, -1.0, 4.0};
  const double l_t[2] = {1.5, 0.5};
  const double l_prev[2] = {1.0, 1.0};  // change (0.5, −0.5)
  ShapeTemporalError cost(2, 2.0);
  const double* parameters[3] = {l_t, l_prev, basis};
  double r[3];
  ASSERT_TRUE(cost.Evaluate(parameters, r, nullptr));
  // 2 · (0.5 · (1, 2, 3) − 0.5 · (0, −1, 4)) = (1, 3, −1).
  EXPECT_DOUBLE_EQ(r[0], 1.0);
  EXPECT_DOUBLE_EQ(r[1], 3.0);
  EXPECT_DOUBLE_EQ(r[2], -1.0);
  ExpectGradientCheckPasses(cost, {l_t, l_prev, basis});
  std::mt19937 rng(13);
  for (int k : {1, 3, 7}) {
    ShapeTemporalError random_cost(k, 0.7);
    const std::vector<double> v = Random(5 * k, &rng);
    ExpectGradientCheckPasses(random_cost,
                              {v.data(), v.data() + k, v.data() + 2 * k});
  }
}

TEST(ShapeTemporalError, InvariantToTheMixingGauge) {
  // S_t − S_{t−1} does not change when weights and basis are mixed by A.
  const int k = 3;
  std::mt19937 rng(14);
  const std::vector<double> v = Random(5 * k, &rng);
  Eigen::Map<const Eigen::VectorXd> l_t(v.data(), k), l_prev(v.data() + k, k);
  Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic>> b(v.data() + 2 * k,
                                                               3, k);
  Eigen::Matrix3d a;
  a << 2.0, 0.5, 0.0, -1.0, 1.0, 0.3, 0.2, 0.0, 1.5;
  const Eigen::VectorXd mixed_t = a.inverse() * l_t;
  const Eigen::VectorXd mixed_prev = a.inverse() * l_prev;
  const Eigen::Matrix<double, 3, Eigen::Dynamic> mixed_b = b * a;
  ShapeTemporalError cost(k, 1.0);
  double r[3], r_mixed[3];
  const double* original[3] = {l_t.data(), l_prev.data(), b.data()};
  const double* mixed[3] = {mixed_t.data(), mixed_prev.data(), mixed_b.data()};
  ASSERT_TRUE(cost.Evaluate(original, r, nullptr));
  ASSERT_TRUE(cost.Evaluate(mixed, r_mixed, nullptr));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r[i], r_mixed[i], 1e-12);
}

TEST(ShapeTemporalError, ProductsGramAndBilinearFormAreThoseOfTheJacobian) {
  // J x, Jᵀ y and the Gram blocks formed from the parameters
  // (problems/jacobian_product.h) against the Jacobian Evaluate() returns;
  // the form r = s · B_p (l_t − l_(t−1)).
  std::mt19937 rng(15);
  for (int k : {1, 2, 5, 12}) {
    ShapeTemporalError cost(k, 0.8);
    testing_util::ExpectProductsEqualTheJacobian(cost, cost, &rng);
    testing_util::ExpectGramEqualsTheJacobian(cost, cost, &rng);
    testing_util::ExpectTheBilinearFormGivesTheResidual(cost, cost, &rng);
  }
}

// Their rows of problems/extra_terms.cc, on F frames, P points, M cameras.
TEST(TemporalTerms, BlocksPerFramePairPointAndCamera) {
  using testing_util::kTermFrames;
  using testing_util::kTermPoints;
  using testing_util::TermBlockCount;
  for (int cameras : {1, 2}) {
    SCOPED_TRACE(cameras);
    const SyntheticSequence s = testing_util::TermTestShoe(cameras);
    EXPECT_EQ(TermBlockCount(kTemporalTerm, s), kTermFrames - 1);  // t ≥ 1
    EXPECT_EQ(TermBlockCount(kTemporalRotationsTerm, s),
              (kTermFrames - 1) * cameras);
    EXPECT_EQ(TermBlockCount(kTemporalShapeTerm, s),
              (kTermFrames - 1) * kTermPoints);
    // 1 ≤ t ≤ F − 2, per camera.
    EXPECT_EQ(TermBlockCount(kRotationAccelerationTerm, s),
              (kTermFrames - 2) * cameras);
  }
}

}  // namespace
}  // namespace nrsfm
