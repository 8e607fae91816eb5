#include "core/model/shape_layouts.h"

#include <glog/logging.h>

namespace nrsfm {
namespace {

std::string SizeString(const Eigen::MatrixXd& m) {
  return std::to_string(m.rows()) + " x " + std::to_string(m.cols());
}

Status CheckThreeFRows(const Eigen::MatrixXd& points, const std::string& name,
                       const std::string& layout) {
  if (points.size() == 0) {
    return Status::Error(name + " is empty (" + SizeString(points) + ")");
  }
  if (points.rows() % 3 != 0) {
    return Status::Error(name + " has " + std::to_string(points.rows()) +
                         " rows, not a multiple of 3 (expected 3F x P, " +
                         layout + ")");
  }
  return Status::OK();
}

}  // namespace

Status FramesFromInterleaved(const Eigen::MatrixXd& points,
                             const std::string& name,
                             std::vector<Eigen::Matrix3Xd>* frames) {
  NRSFM_RETURN_IF_ERROR(
      CheckThreeFRows(points, name, "rows x_t, y_t, z_t interleaved"));
  const Eigen::Index num_frames = points.rows() / 3;
  frames->resize(num_frames);
  for (Eigen::Index t = 0; t < num_frames; ++t)
    (*frames)[t] = points.middleRows(3 * t, 3);
  return Status::OK();
}

Status FramesFromBlockLayout(const Eigen::MatrixXd& points,
                             const std::string& name,
                             std::vector<Eigen::Matrix3Xd>* frames) {
  NRSFM_RETURN_IF_ERROR(
      CheckThreeFRows(points, name, "block layout [x rows; y rows; z rows]"));
  const Eigen::Index num_frames = points.rows() / 3;
  frames->resize(num_frames);
  for (Eigen::Index t = 0; t < num_frames; ++t) {
    Eigen::Matrix3Xd& frame = (*frames)[t];
    frame.resize(3, points.cols());
    frame.row(0) = points.row(t);
    frame.row(1) = points.row(num_frames + t);
    frame.row(2) = points.row(2 * num_frames + t);
  }
  return Status::OK();
}

Status FramesFromArray3(const std::vector<Eigen::MatrixXd>& slices,
                        const std::string& name,
                        std::vector<Eigen::Matrix3Xd>* frames) {
  if (slices.empty() || slices[0].size() == 0) {
    return Status::Error(name + " is empty; expected a 3 x P x F array");
  }
  for (std::size_t t = 0; t < slices.size(); ++t) {
    if (slices[t].rows() != 3 || slices[t].cols() != slices[0].cols()) {
      return Status::Error(name + " is " + SizeString(slices[0]) + " x " +
                           std::to_string(slices.size()) +
                           (t == 0 ? ""
                                   : " with slice " + std::to_string(t) + " " +
                                         SizeString(slices[t])) +
                           "; expected 3 x P x F");
    }
  }
  frames->assign(slices.begin(), slices.end());
  return Status::OK();
}

Eigen::MatrixXd OrthographicW(const std::vector<Eigen::Matrix3Xd>& frames) {
  const Eigen::Index num_points = frames.empty() ? 0 : frames[0].cols();
  Eigen::MatrixXd w(2 * frames.size(), num_points);
  for (std::size_t t = 0; t < frames.size(); ++t) {
    CHECK_EQ(frames[t].cols(), num_points);
    w.middleRows(2 * t, 2) = frames[t].topRows<2>();
  }
  return w;
}

}  // namespace nrsfm
