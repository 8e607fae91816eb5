// The angle-axis of a product of rotations, for the residuals that compare
// rotations (problems/rigidity_error.h, problems/temporal_error.h):
//
//   log( R(a) R(b)ᵀ R(c)ᵀ )     (c = nullptr: log( R(a) R(b)ᵀ ))
//
// a, b, c angle-axis vectors (ceres/rotation.h convention, radians); the
// result is an angle-axis vector with angle in [0, π]: its norm is the angle
// of the discrepancy. Computed through unit quaternions (the formulas of
// ceres/rotation.h, with exact derivatives at the identity), written so that
// the double and the Jet evaluations round identically: the only division
// is 1 / x, never x / Jet (a Jet divides through the reciprocal). Near the
// identity the result is a small difference of O(1) numbers, so any rounding
// difference between the two evaluations would show up in the residual.
#ifndef NRSFM_PROBLEMS_RELATIVE_ROTATION_H_
#define NRSFM_PROBLEMS_RELATIVE_ROTATION_H_

#include <ceres/rotation.h>

#include <cmath>

namespace nrsfm {
namespace internal {

template <typename T>
void ToQuaternion(const T* angle_axis, T* q) {
  const T theta_squared = angle_axis[0] * angle_axis[0] +
                          angle_axis[1] * angle_axis[1] +
                          angle_axis[2] * angle_axis[2];
  if (theta_squared > T(0.0)) {
    using std::cos;
    using std::sin;
    using std::sqrt;
    const T theta = sqrt(theta_squared);
    const T half_theta = T(0.5) * theta;
    const T k = sin(half_theta) * (T(1.0) / theta);
    q[0] = cos(half_theta);
    q[1] = angle_axis[0] * k;
    q[2] = angle_axis[1] * k;
    q[3] = angle_axis[2] * k;
  } else {
    // sin(θ/2) / θ → 1/2: exact to first order, so the derivative is exact.
    q[0] = T(1.0);
    q[1] = angle_axis[0] * T(0.5);
    q[2] = angle_axis[1] * T(0.5);
    q[3] = angle_axis[2] * T(0.5);
  }
}

template <typename T>
void ToAngleAxis(const T* q, T* angle_axis) {
  const T sin_squared = q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
  T k(2.0);  // 2θ / sin θ → 2 at θ = 0
  if (sin_squared > T(0.0)) {
    using std::atan2;
    using std::sqrt;
    const T sin_theta = sqrt(sin_squared);
    const T& cos_theta = q[0];
    // θ in [0, π]: q and −q are the same rotation.
    const T two_theta =
        T(2.0) * ((cos_theta < T(0.0)) ? atan2(-sin_theta, -cos_theta)
                                       : atan2(sin_theta, cos_theta));
    k = two_theta * (T(1.0) / sin_theta);
  }
  angle_axis[0] = q[1] * k;
  angle_axis[1] = q[2] * k;
  angle_axis[2] = q[3] * k;
}

template <typename T>
void ConjugateInPlace(T* q) {
  q[1] = -q[1];
  q[2] = -q[2];
  q[3] = -q[3];
}

}  // namespace internal

template <typename T>
void RelativeAngleAxis(const T* a, const T* b, const T* c, T* angle_axis) {
  T qa[4];
  T qb[4];
  internal::ToQuaternion(a, qa);
  internal::ToQuaternion(b, qb);
  internal::ConjugateInPlace(qb);  // the inverse of a unit quaternion
  T product[4];
  ceres::QuaternionProduct(qa, qb, product);
  if (c != nullptr) {
    T qc[4];
    internal::ToQuaternion(c, qc);
    internal::ConjugateInPlace(qc);
    T with_c[4];
    ceres::QuaternionProduct(product, qc, with_c);
    internal::ToAngleAxis(with_c, angle_axis);
  } else {
    internal::ToAngleAxis(product, angle_axis);
  }
}

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_RELATIVE_ROTATION_H_
