#include "core/io/ground_truth.h"

#include <Eigen/Geometry>
#include <algorithm>

#include "core/io/mat_io.h"
#include "core/model/shape_layouts.h"

namespace nrsfm {
namespace {

bool Has(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

Status ReadFromSAndRs(const std::string& path, GroundTruth* truth) {
  Eigen::MatrixXd s, rs;
  NRSFM_RETURN_IF_ERROR(ReadMatVariable(path, "S", &s));
  NRSFM_RETURN_IF_ERROR(ReadMatVariable(path, "Rs", &rs));
  std::vector<Eigen::Matrix3Xd> frames;
  NRSFM_RETURN_IF_ERROR(FramesFromInterleaved(s, path + ": S", &frames));
  const Eigen::Index num_frames = static_cast<Eigen::Index>(frames.size());
  if (rs.rows() != 2 * num_frames || rs.cols() != 3) {
    return Status::Error(path + ": Rs is " + std::to_string(rs.rows()) + " x " +
                         std::to_string(rs.cols()) + "; expected 2F x 3 = " +
                         std::to_string(2 * num_frames) + " x 3 for S with " +
                         std::to_string(s.rows()) +
                         " rows (F = " + std::to_string(num_frames) + ")");
  }
  if (!rs.allFinite()) return Status::Error(path + ": Rs holds NaN or Inf");
  truth->points_in_camera.resize(num_frames);
  truth->rotations.resize(num_frames);
  for (Eigen::Index t = 0; t < num_frames; ++t) {
    const Eigen::Vector3d r1 = rs.row(2 * t).transpose();
    const Eigen::Vector3d r2 = rs.row(2 * t + 1).transpose();
    Eigen::Matrix3d rotation;
    rotation << r1.transpose(), r2.transpose(), r1.cross(r2).transpose();
    // Rs holds the first two rows of a rotation; anything else (a scaled or
    // sheared camera) would make the object-frame score meaningless.
    if ((rotation * rotation.transpose() - Eigen::Matrix3d::Identity())
            .cwiseAbs()
            .maxCoeff() > 1e-3) {
      return Status::Error(path + ": Rs rows " + std::to_string(2 * t + 1) +
                           "-" + std::to_string(2 * t + 2) + " (frame " +
                           std::to_string(t) +
                           ") are not two orthonormal rows of a rotation");
    }
    truth->rotations[t] = rotation;
    truth->points_in_camera[t] = rotation * frames[t];
  }
  truth->points_in_object = std::move(frames);
  truth->source = "S+Rs";
  return Status::OK();
}

}  // namespace

Status ReadGroundTruth(const std::string& path, const std::string& variable,
                       GroundTruth* truth) {
  std::string chosen = variable;
  if (chosen.empty()) {
    std::vector<std::string> names;
    NRSFM_RETURN_IF_ERROR(ListMatVariables(path, &names));
    if (Has(names, "S") && Has(names, "Rs")) {
      chosen = "S";
    } else if (Has(names, "P3_gt")) {
      chosen = "P3_gt";
    } else if (Has(names, "X")) {
      chosen = "X";
    } else {
      std::string joined;
      for (const std::string& name : names)
        joined += (joined.empty() ? "" : ", ") + name;
      return Status::Error(
          path +
          ": no ground truth (S with Rs, P3_gt or X) in the file; it has: " +
          (joined.empty() ? "(none)" : joined));
    }
  }
  GroundTruth result;
  if (chosen == "S") {
    NRSFM_RETURN_IF_ERROR(ReadFromSAndRs(path, &result));
  } else if (chosen == "P3_gt") {
    Eigen::MatrixXd block;
    NRSFM_RETURN_IF_ERROR(ReadMatVariable(path, chosen, &block));
    NRSFM_RETURN_IF_ERROR(FramesFromBlockLayout(block, path + ": P3_gt",
                                                &result.points_in_camera));
    result.source = "P3_gt";
  } else if (chosen == "X") {
    std::vector<Eigen::MatrixXd> slices;
    std::vector<std::size_t> dims;
    NRSFM_RETURN_IF_ERROR(ReadMatArray3(path, chosen, &slices, &dims));
    if (slices.empty()) {
      return Status::Error(path + ": X is empty (" + MatDimsString(dims) +
                           "); expected a 3 x P x F array");
    }
    NRSFM_RETURN_IF_ERROR(
        FramesFromArray3(slices, path + ": X", &result.points_in_camera));
    result.source = "X";
  } else {
    return Status::Error(
        path + ": '" + chosen +
        "' is not a ground-truth variable; use S (with Rs), P3_gt or X");
  }
  for (std::size_t t = 0; t < result.points_in_camera.size(); ++t) {
    if (!result.points_in_camera[t].allFinite()) {
      return Status::Error(path + ": ground truth " + chosen +
                           " holds NaN or Inf (frame " + std::to_string(t) +
                           ")");
    }
  }
  *truth = std::move(result);
  return Status::OK();
}

}  // namespace nrsfm
