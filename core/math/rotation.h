// Rotation helpers shared by the whole library (Eigen only; the Ceres
// residuals use ceres/rotation.h, which follows the same angle-axis
// convention: direction = axis, norm = angle in radians).
#ifndef NRSFM_CORE_MATH_ROTATION_H_
#define NRSFM_CORE_MATH_ROTATION_H_

#include <Eigen/Core>

namespace nrsfm {

Eigen::Matrix3d AngleAxisToRotation(const Eigen::Vector3d& angle_axis);
Eigen::Vector3d RotationToAngleAxis(const Eigen::Matrix3d& rotation);

// The rotation nearest to `m` in the Frobenius norm (SVD, det = +1).
Eigen::Matrix3d NearestRotation(const Eigen::Matrix3d& m);

// Angle of R_a R_bᵀ in radians, in [0, π].
double RotationAngleBetween(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b);

}  // namespace nrsfm

#endif  // NRSFM_CORE_MATH_ROTATION_H_
