#include "core/model/model.h"

#include <glog/logging.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "core/math/rotation.h"
#include "core/math/svd.h"
#include "core/model/enum_names.h"

namespace nrsfm {
namespace {

constexpr EnumName<CameraModel> kCameraModelNames[] = {
    {CameraModel::kWeakPerspective, "weak_perspective"},
    {CameraModel::kPerspective, "perspective"},
};

}  // namespace

const char* CameraModelName(CameraModel camera) {
  return NameOf(kCameraModelNames, camera);
}

Status ParseCameraModel(const std::string& name, CameraModel* camera) {
  return ParseName(kCameraModelNames, name, "camera model", camera);
}

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
  camera = CameraModel::kWeakPerspective;
  depths = Eigen::RowVectorXd::Zero(NumViews());
  intrinsics.resize(4, 0);
}

Eigen::Matrix3d Model::Rotation(int frame, int camera) const {
  return AngleAxisToRotation(rotations.col(View(frame, camera)));
}

void Model::SetRotation(int frame, int camera,
                        const Eigen::Matrix3d& rotation) {
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
  const int view = View(frame, camera);
  if (this->camera == CameraModel::kPerspective) {
    Eigen::Matrix3Xd shape = Rotation(frame, camera) * ShapeInObject(frame);
    shape.colwise() += Eigen::Vector3d(translations(0, view),
                                       translations(1, view), depths(view));
    return shape;
  }
  return scales(view) * Rotation(frame, camera) * ShapeInObject(frame);
}

Eigen::Matrix2Xd Model::Project(int frame, int camera) const {
  const Eigen::Matrix3Xd shape = ShapeInCamera(frame, camera);
  if (this->camera == CameraModel::kPerspective) {
    const Eigen::Vector4d k = intrinsics.col(camera);
    Eigen::Matrix2Xd projected(2, shape.cols());
    projected.row(0) = k(0) * shape.row(0).cwiseQuotient(shape.row(2));
    projected.row(1) = k(1) * shape.row(1).cwiseQuotient(shape.row(2));
    projected.row(0).array() += k(2);
    projected.row(1).array() += k(3);
    return projected;
  }
  Eigen::Matrix2Xd projected = shape.topRows<2>();
  projected.colwise() += translations.col(View(frame, camera));
  return projected;
}

bool Model::MakeFirstBasisTheMean() {
  const int k = num_bases;
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(k);
  int count = 0;
  for (int t = 0; t < num_frames; ++t) {
    if (!weights.col(t).allFinite()) continue;
    mean += weights.col(t);
    ++count;
  }
  if (count == 0) return false;
  mean /= count;
  const double norm = mean.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) return false;
  // Q orthonormal with first column u = mean / |mean| (a Householder
  // reflection), A⁻¹ = Q diag(|mean|, 1, …, 1): A⁻¹ e_1 = mean, so A mean =
  // e_1.
  Eigen::VectorXd v = mean / norm;
  v(0) -= 1.0;
  Eigen::MatrixXd q = Eigen::MatrixXd::Identity(k, k);
  if (v.squaredNorm() > 1e-30) q -= 2.0 * v * v.transpose() / v.squaredNorm();
  Eigen::MatrixXd inverse = q;  // A⁻¹ = Q D
  inverse.col(0) *= norm;
  Eigen::MatrixXd a = q.transpose();  // A = D⁻¹ Qᵀ
  a.row(0) /= norm;
  for (int t = 0; t < num_frames; ++t) {
    if (weights.col(t).allFinite()) weights.col(t) = a * weights.col(t);
  }
  // New shape j = Σ_k (A⁻¹)_kj S_k.
  Eigen::MatrixXd old_basis = basis;
  for (int p = 0; p < num_points; ++p) {
    for (int j = 0; j < k; ++j) {
      Eigen::Vector3d shape = Eigen::Vector3d::Zero();
      for (int i = 0; i < k; ++i)
        shape += inverse(i, j) * old_basis.block<3, 1>(3 * i, p);
      basis.block<3, 1>(3 * j, p) = shape;
    }
  }
  return true;
}

Status Model::Validate(bool allow_nan) const {
  std::ostringstream msg;
  if (num_frames < 1 || num_cameras < 1 || num_points < 1 || num_bases < 1) {
    msg << "model: need F, M, P, K >= 1; got F = " << num_frames
        << ", M = " << num_cameras << ", P = " << num_points
        << ", K = " << num_bases;
    return Status::Error(msg.str());
  }
  auto check = [&](const char* name, const Eigen::MatrixXd& m,
                   Eigen::Index rows, Eigen::Index cols) -> Status {
    if (m.rows() != rows || m.cols() != cols) {
      std::ostringstream s;
      s << "model: " << name << " is " << m.rows() << " x " << m.cols()
        << ", expected " << rows << " x " << cols;
      return Status::Error(s.str());
    }
    if (allow_nan ? m.array().isInf().any() : !m.allFinite()) {
      return Status::Error(std::string("model: ") + name +
                           (allow_nan ? " has an infinite value"
                                      : " has a NaN or infinite value"));
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
  NRSFM_RETURN_IF_ERROR(check("depths", depths, 1, NumViews()));
  if (camera == CameraModel::kPerspective) {
    NRSFM_RETURN_IF_ERROR(check("intrinsics", intrinsics, 4, num_cameras));
    if (!(intrinsics.row(0).array() > 0.0).all() ||
        !(intrinsics.row(1).array() > 0.0).all()) {
      return Status::Error(
          "model: the focal lengths fx, fy of a perspective camera must be "
          "positive");
    }
  }
  return Status::OK();
}

Model ReduceNumBases(const Model& model, int num_bases) {
  CHECK(num_bases >= 1 && num_bases <= model.num_bases)
      << "num_bases " << num_bases << " of " << model.num_bases;
  std::vector<int> frames;
  for (int t = 0; t < model.num_frames; ++t) {
    if (model.weights.col(t).allFinite()) frames.push_back(t);
  }
  const int p3 = 3 * model.num_points;
  Eigen::MatrixXd shapes(frames.size(), p3);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const Eigen::Matrix3Xd shape = model.ShapeInObject(frames[i]);
    shapes.row(i) = Eigen::Map<const Eigen::RowVectorXd>(shape.data(), p3);
  }
  Model reduced = model;
  reduced.num_bases = num_bases;
  reduced.weights = Eigen::MatrixXd::Constant(
      num_bases, model.num_frames, std::numeric_limits<double>::quiet_NaN());
  reduced.basis = Eigen::MatrixXd::Zero(3 * num_bases, model.num_points);
  if (frames.empty()) return reduced;
  const ThinSvd svd = ComputeThinSvd(shapes, SingularVectors::kBoth);
  const int rank = std::min<int>(num_bases, svd.singular_values.size());
  for (int k = 0; k < rank; ++k) {
    const Eigen::VectorXd column = svd.v.col(k);
    reduced.SetBasisShape(k, Eigen::Map<const Eigen::Matrix3Xd>(
                                 column.data(), 3, model.num_points));
  }
  for (std::size_t i = 0; i < frames.size(); ++i) {
    reduced.weights.col(frames[i]).setZero();
    for (int k = 0; k < rank; ++k) {
      reduced.weights(k, frames[i]) = svd.u(i, k) * svd.singular_values(k);
    }
  }
  return reduced;
}

}  // namespace nrsfm
