#include "problems/rotation_manifold.h"

#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>

#include "core/math/rotation.h"

namespace nrsfm {
namespace {

using RowMajor3d = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

Eigen::Matrix3d Hat(const Eigen::Vector3d& w) {
  Eigen::Matrix3d hat;
  hat << 0, -w(2), w(1), w(2), 0, -w(0), -w(1), w(0), 0;
  return hat;
}

Eigen::Matrix3d InverseRightJacobian(const Eigen::Vector3d& w) {
  const double theta = w.norm();
  const Eigen::Matrix3d hat = Hat(w);
  // The coefficient of [w]×², with its series 1/12 + θ²/720 near θ = 0.
  const double c =
      theta > 1e-4 ? 1.0 / (theta * theta) - (1.0 + std::cos(theta)) /
                                                 (2.0 * theta * std::sin(theta))
                   : 1.0 / 12.0 + theta * theta / 720.0;
  return Eigen::Matrix3d::Identity() + 0.5 * hat + c * hat * hat;
}

}  // namespace

bool AngleAxisManifold::Plus(const double* x, const double* delta,
                             double* out) const {
  const Eigen::Matrix3d r =
      AngleAxisToRotation(Eigen::Vector3d(x[0], x[1], x[2])) *
      AngleAxisToRotation(Eigen::Vector3d(delta[0], delta[1], delta[2]));
  Eigen::Map<Eigen::Vector3d> result(out);
  result = RotationToAngleAxis(r);
  return true;
}

bool AngleAxisManifold::PlusJacobian(const double* x, double* jacobian) const {
  Eigen::Map<RowMajor3d> result(jacobian);
  result = InverseRightJacobian(Eigen::Vector3d(x[0], x[1], x[2]));
  return true;
}

bool AngleAxisManifold::Minus(const double* y, const double* x,
                              double* out) const {
  const Eigen::Matrix3d r =
      AngleAxisToRotation(Eigen::Vector3d(x[0], x[1], x[2])).transpose() *
      AngleAxisToRotation(Eigen::Vector3d(y[0], y[1], y[2]));
  Eigen::Map<Eigen::Vector3d> result(out);
  result = RotationToAngleAxis(r);
  return true;
}

bool AngleAxisManifold::MinusJacobian(const double* x, double* jacobian) const {
  Eigen::Map<RowMajor3d> result(jacobian);
  result = InverseRightJacobian(Eigen::Vector3d(x[0], x[1], x[2])).inverse();
  return true;
}

}  // namespace nrsfm
