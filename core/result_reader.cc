#include "core/result_reader.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/text_io.h"

namespace nrsfm {
namespace {

// An index column value: integral and in [0, 2^31).
bool IsIndex(double value) {
  return value >= 0 && value < 2147483647.0 && value == std::floor(value);
}

}  // namespace

Status ReadPointsCameraCsv(const std::string& path, int camera,
                           GroundTruth* truth) {
  std::error_code ec;
  std::string file = path;
  if (std::filesystem::is_directory(path, ec)) {
    file = (std::filesystem::path(path) / "points_camera.csv").string();
  }
  Eigen::MatrixXd table;
  NRSFM_RETURN_IF_ERROR(
      ReadCsvTable(file, {"frame", "camera", "point", "x", "y", "z"}, &table));
  // Errors name the data row (1-based, the header not counted).
  long num_frames = 0, num_points = 0, rows_of_camera = 0;
  for (Eigen::Index r = 0; r < table.rows(); ++r) {
    for (int j = 0; j < 3; ++j) {
      if (!IsIndex(table(r, j))) {
        return Status::Error(file + ": data row " + std::to_string(r + 1) +
                             ", column " + std::to_string(j + 1) +
                             ": not a non-negative integer index");
      }
    }
    if (static_cast<int>(table(r, 1)) != camera) continue;
    ++rows_of_camera;
    num_frames = std::max(num_frames, static_cast<long>(table(r, 0)) + 1);
    num_points = std::max(num_points, static_cast<long>(table(r, 2)) + 1);
  }
  if (rows_of_camera == 0) {
    return Status::Error(file + ": no rows for camera " +
                         std::to_string(camera));
  }
  if (num_frames * num_points != rows_of_camera) {
    return Status::Error(
        file + ": camera " + std::to_string(camera) + " has " +
        std::to_string(rows_of_camera) +
        " rows, but its indices imply F = " + std::to_string(num_frames) +
        " frames x P = " + std::to_string(num_points) + " points");
  }
  GroundTruth result;
  result.source = "points_camera.csv";
  result.points_in_camera.assign(
      num_frames, Eigen::Matrix3Xd::Constant(3, num_points, NAN));
  Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> seen =
      Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic>::Constant(
          num_frames, num_points, false);
  for (Eigen::Index r = 0; r < table.rows(); ++r) {
    if (static_cast<int>(table(r, 1)) != camera) continue;
    const int t = static_cast<int>(table(r, 0));
    const int p = static_cast<int>(table(r, 2));
    const std::string where = file + ": frame " + std::to_string(t) +
                              ", point " + std::to_string(p) + ", camera " +
                              std::to_string(camera);
    if (seen(t, p)) return Status::Error(where + " appears twice");
    seen(t, p) = true;
    const Eigen::Vector3d x = table.block<1, 3>(r, 3).transpose();
    if (!x.allFinite())
      return Status::Error(where + ": coordinates are not finite");
    result.points_in_camera[t].col(p) = x;
  }
  *truth = std::move(result);
  return Status::OK();
}

}  // namespace nrsfm
