#include "core/math/rotation.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>

namespace nrsfm {

Eigen::Matrix3d AngleAxisToRotation(const Eigen::Vector3d& angle_axis) {
  const double angle = angle_axis.norm();
  if (angle < 1e-300) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, angle_axis / angle).toRotationMatrix();
}

Eigen::Vector3d RotationToAngleAxis(const Eigen::Matrix3d& rotation) {
  const Eigen::AngleAxisd aa(rotation);
  return aa.angle() * aa.axis();
}

Eigen::Matrix3d NearestRotation(const Eigen::Matrix3d& m) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(
      m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0
                                                                          : 1.0;
  return svd.matrixU() * d * svd.matrixV().transpose();
}

double RotationAngleBetween(const Eigen::Matrix3d& a,
                            const Eigen::Matrix3d& b) {
  // Via the quaternion (atan2 inside Eigen): accurate for small angles too,
  // unlike acos((trace - 1) / 2).
  return Eigen::AngleAxisd(NearestRotation(a * b.transpose())).angle();
}

}  // namespace nrsfm
