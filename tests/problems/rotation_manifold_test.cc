// Hand-computed values and numerical Jacobian checks of
// problems/rotation_manifold.h.
#include "problems/rotation_manifold.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>

#include "core/math/rotation.h"

namespace nrsfm {
namespace {

using RowMajor3d = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

Eigen::Vector3d Plus(const Eigen::Vector3d& x, const Eigen::Vector3d& delta) {
  Eigen::Vector3d out;
  EXPECT_TRUE(AngleAxisManifold().Plus(x.data(), delta.data(), out.data()));
  return out;
}

TEST(AngleAxisManifold, HandComputedPlusAboutOneAxis) {
  // Rotations about one axis commute: the angles add.
  const Eigen::Vector3d x(0, 0, M_PI / 2);
  const Eigen::Vector3d out = Plus(x, Eigen::Vector3d(0, 0, 0.1));
  EXPECT_NEAR(out(0), 0.0, 1e-15);
  EXPECT_NEAR(out(1), 0.0, 1e-15);
  EXPECT_NEAR(out(2), M_PI / 2 + 0.1, 1e-14);
  // From the identity the update is the step itself.
  const Eigen::Vector3d delta(0.3, -0.2, 0.1);
  EXPECT_LT((Plus(Eigen::Vector3d::Zero(), delta) - delta).norm(), 1e-15);
  // A zero step leaves x.
  EXPECT_LT((Plus(x, Eigen::Vector3d::Zero()) - x).norm(), 1e-15);
}

TEST(AngleAxisManifold, StepIsInTheBodyFrame) {
  // exp(x) exp(δ), not exp(δ) exp(x): with x a quarter turn about z and δ a
  // small turn about x, the result is R_z(π/2) R_x(0.2).
  const Eigen::Vector3d x(0, 0, M_PI / 2), delta(0.2, 0, 0);
  const Eigen::Matrix3d expected =
      AngleAxisToRotation(x) * AngleAxisToRotation(delta);
  EXPECT_LT((AngleAxisToRotation(Plus(x, delta)) - expected).norm(), 1e-14);
  const Eigen::Matrix3d wrong_order =
      AngleAxisToRotation(delta) * AngleAxisToRotation(x);
  EXPECT_GT((AngleAxisToRotation(Plus(x, delta)) - wrong_order).norm(), 0.1);
}

TEST(AngleAxisManifold, MinusInvertsPlus) {
  const AngleAxisManifold manifold;
  const Eigen::Vector3d xs[] = {
      {0.1, -0.2, 0.3}, {2.0, 1.0, -1.5}, {0, 0, 3.1}};
  const Eigen::Vector3d delta(0.05, 0.2, -0.1);
  for (const Eigen::Vector3d& x : xs) {
    const Eigen::Vector3d y = Plus(x, delta);
    Eigen::Vector3d back;
    ASSERT_TRUE(manifold.Minus(y.data(), x.data(), back.data()));
    EXPECT_LT((back - delta).norm(), 1e-13) << x.transpose();
  }
}

TEST(AngleAxisManifold, JacobiansMatchCentralDifferences) {
  const AngleAxisManifold manifold;
  // Small, large and near-π angles (the additive update is worst there).
  const Eigen::Vector3d xs[] = {
      {1e-7, 0, 0}, {0.1, -0.2, 0.3}, {2.0, 1.0, -1.5}, {0, 3.0, 0.5}};
  const double h = 1e-6;
  for (const Eigen::Vector3d& x : xs) {
    RowMajor3d plus_jacobian, minus_jacobian;
    ASSERT_TRUE(manifold.PlusJacobian(x.data(), plus_jacobian.data()));
    ASSERT_TRUE(manifold.MinusJacobian(x.data(), minus_jacobian.data()));
    Eigen::Matrix3d numeric;
    for (int j = 0; j < 3; ++j) {
      Eigen::Vector3d step = Eigen::Vector3d::Zero();
      step(j) = h;
      numeric.col(j) = (Plus(x, step) - Plus(x, -step)) / (2 * h);
    }
    EXPECT_LT((plus_jacobian - numeric).norm(), 1e-7) << x.transpose();
    EXPECT_LT(
        (minus_jacobian * plus_jacobian - Eigen::Matrix3d::Identity()).norm(),
        1e-12)
        << x.transpose();
  }
}

}  // namespace
}  // namespace nrsfm
