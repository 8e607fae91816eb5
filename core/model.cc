#include "core/model.h"

#include <sstream>

#include <Eigen/Geometry>
#include <glog/logging.h>

#include "core/rotation.h"

namespace nrsfm {

void Model::Resize(int frames, int cameras, int points, int bases) {
  CHECK_GE(frames, 0);
  CHECK_GE(cameras, 1);
  CHECK_GE(points, 0);
  CHECK_GE(bases, 0);
  num_frames = frames;
  num_cameras = cameras;
  num_points = points;
  num_bases = bases;
  rotations = Eigen::Matrix3Xd::Zero(3, NumViews());
  translations = Eigen::Matrix2Xd::Zero(2, NumViews());
  weights = Eigen::MatrixXd::Zero(bases, frames);
  basis = Eigen::MatrixXd::Zero(3 * bases, points);
  scales = Eigen::RowVectorXd::Ones(NumViews());
  rig_rotations = Eigen::Matrix3Xd::Zero(3, cameras - 1);
  rig_scales = Eigen::RowVectorXd::Ones(cameras - 1);
}

Eigen::Matrix3d Model::Rotation(int frame, int camera) const {
  return AngleAxisToRotation(rotations.col(View(frame, camera)));
}

void Model::SetRotation(int frame, int camera, const Eigen::Matrix3d& rotation) {
  rotations.col(View(frame, camera)) = RotationToAngleAxis(rotation);
}

Eigen::Matrix3Xd Model::BasisShape(int k) const {
  return basis.middleRows(3 * k, 3);
}

void Model::SetBasisShape(int k, const Eigen::Matrix3Xd& shape) {
  basis.middleRows(3 * k, 3) = shape;
}

Eigen::Matrix3Xd Model::ShapeInObject(int frame) const {
  Eigen::Matrix3Xd shape = Eigen::Matrix3Xd::Zero(3, num_points);
  for (int k = 0; k < num_bases; ++k) {
    shape += weights(k, frame) * basis.middleRows(3 * k, 3);
  }
  return shape;
}

Eigen::Matrix3Xd Model::ShapeInCamera(int frame, int camera) const {
  return scales(View(frame, camera)) * Rotation(frame, camera) *
         ShapeInObject(frame);
}

Eigen::Matrix2Xd Model::Project(int frame, int camera) const {
  Eigen::Matrix2Xd projected = ShapeInCamera(frame, camera).topRows<2>();
  projected.colwise() += translations.col(View(frame, camera));
  return projected;
}

Status Model::Validate(bool allow_nan) const {
  std::ostringstream msg;
  if (num_frames < 1 || num_cameras < 1 || num_points < 1 || num_bases < 1) {
    msg << "model: need F, M, P, K >= 1; got F = " << num_frames
        << ", M = " << num_cameras << ", P = " << num_points
        << ", K = " << num_bases;
    return Status::Error(msg.str());
  }
  auto check = [&](const char* name, const Eigen::MatrixXd& m, Eigen::Index rows,
                   Eigen::Index cols) -> Status {
    if (m.rows() != rows || m.cols() != cols) {
      std::ostringstream s;
      s << "model: " << name << " is " << m.rows() << " x " << m.cols()
        << ", expected " << rows << " x " << cols;
      return Status::Error(s.str());
    }
    if (allow_nan ? m.array().isInf().any() : !m.allFinite()) {
      return Status::Error(std::string("model: ") + name +
                           (allow_nan ? " has an infinite value" : " has a NaN or infinite value"));
    }
    return Status::OK();
  };
  NRSFM_RETURN_IF_ERROR(check("rotations", rotations, 3, NumViews()));
  NRSFM_RETURN_IF_ERROR(check("translations", translations, 2, NumViews()));
  NRSFM_RETURN_IF_ERROR(check("weights", weights, num_bases, num_frames));
  NRSFM_RETURN_IF_ERROR(check("basis", basis, 3 * num_bases, num_points));
  NRSFM_RETURN_IF_ERROR(check("scales", scales, 1, NumViews()));
  NRSFM_RETURN_IF_ERROR(
      check("rig_rotations", rig_rotations, 3, num_cameras - 1));
  NRSFM_RETURN_IF_ERROR(check("rig_scales", rig_scales, 1, num_cameras - 1));
  return Status::OK();
}

}  // namespace nrsfm
