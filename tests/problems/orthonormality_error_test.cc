// Hand-computed residuals, gauge invariance and Jacobian checks of
// problems/orthonormality_error.h.
#include "problems/orthonormality_error.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <memory>
#include <random>
#include <vector>

#include "tests/problems/functor_test_util.h"

namespace nrsfm {
namespace {

using testing_util::ExpectGradientCheckPasses;
using testing_util::Random;

double Residual(const Eigen::RowVectorXd& q1, const Eigen::RowVectorXd& q2,
                const Eigen::MatrixXd& g, double r[2]) {
  std::unique_ptr<ceres::CostFunction> cost(
      OrthonormalityError::Create(q1, q2));
  const double* parameters[1] = {g.data()};
  EXPECT_TRUE(cost->Evaluate(parameters, r, nullptr));
  return std::hypot(r[0], r[1]);
}

TEST(OrthonormalityError, HandComputedResidual) {
  // K = 1, G = I: a1 = (1, 0, 1), a2 = (0, 2, 1); |a1|² = 2, |a2|² = 5,
  // a1·a2 = 1, so r = ((2 − 5) / 7, 2 / 7).
  Eigen::RowVector3d q1(1, 0, 1), q2(0, 2, 1);
  std::unique_ptr<ceres::CostFunction> cost(
      OrthonormalityError::Create(q1, q2));
  EXPECT_EQ(cost->num_residuals(), 2);
  ASSERT_EQ(cost->parameter_block_sizes(), (std::vector<int32_t>{3 * 3}));
  double r[2];
  Residual(q1, q2, Eigen::MatrixXd::Identity(3, 3), r);
  EXPECT_DOUBLE_EQ(r[0], -3.0 / 7.0);
  EXPECT_DOUBLE_EQ(r[1], 2.0 / 7.0);
}

// Rows of c Π R give r = 0, whatever the scale c, and r is unchanged by the
// gauges G → α G U.
TEST(OrthonormalityError, ZeroForAScaledRotationAndGaugeInvariant) {
  const int k = 2;
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, -2, 0.5).normalized())
          .toRotationMatrix();
  // G stacks the identity over 0, so q G = first three entries of q.
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(3 * k, 3);
  g.topRows<3>().setIdentity();
  Eigen::RowVectorXd q1 = Eigen::RowVectorXd::Zero(3 * k), q2 = q1;
  q1.head<3>() = 2.5 * rotation.row(0);
  q2.head<3>() = 2.5 * rotation.row(1);
  q1.tail<3>() << 0.3, -0.1, 0.7;  // ignored by this G
  double r[2];
  EXPECT_LT(Residual(q1, q2, g, r), 1e-15);

  std::mt19937 rng(5);
  const std::vector<double> values = Random(3 * 3 * k, &rng);
  const Eigen::MatrixXd generic =
      Eigen::Map<const Eigen::MatrixXd>(values.data(), 3 * k, 3);
  double before[2], after[2];
  Residual(q1, q2, generic, before);
  const Eigen::Matrix3d u =
      Eigen::AngleAxisd(1.1, Eigen::Vector3d(0, 1, 1).normalized())
          .toRotationMatrix() *
      Eigen::Vector3d(1, 1, -1).asDiagonal();  // a rotation times a reflection
  Residual(q1, q2, -3.0 * generic * u, after);
  EXPECT_GT(std::hypot(before[0], before[1]), 1e-3);
  EXPECT_NEAR(after[0], before[0], 1e-14);
  EXPECT_NEAR(after[1], before[1], 1e-14);
}

TEST(OrthonormalityError, UndefinedWhenBothRowsVanish) {
  Eigen::RowVector3d q1(1, 0, 0), q2(0, 1, 0);
  std::unique_ptr<ceres::CostFunction> cost(
      OrthonormalityError::Create(q1, q2));
  const Eigen::MatrixXd g = Eigen::MatrixXd::Zero(3, 3);
  const double* parameters[1] = {g.data()};
  double r[2];
  EXPECT_FALSE(cost->Evaluate(parameters, r, nullptr));
}

TEST(OrthonormalityError, GradientChecker) {
  std::mt19937 rng(7);
  for (const int k : {1, 2, 4}) {
    const std::vector<double> q1 = Random(3 * k, &rng),
                              q2 = Random(3 * k, &rng);
    std::unique_ptr<ceres::CostFunction> cost(OrthonormalityError::Create(
        Eigen::Map<const Eigen::RowVectorXd>(q1.data(), 3 * k),
        Eigen::Map<const Eigen::RowVectorXd>(q2.data(), 3 * k)));
    const std::vector<double> g = Random(3 * 3 * k, &rng);
    ExpectGradientCheckPasses(*cost, {g.data()});
  }
}

}  // namespace
}  // namespace nrsfm
