#include "core/io/result_reader.h"

#include <glog/logging.h>

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "core/io/text_io.h"

namespace nrsfm {
namespace {

// An index column value: integral and in [0, 2^31).
bool IsIndex(double value) {
  return value >= 0 && value < 2147483647.0 && value == std::floor(value);
}

// Checks that columns 0 … num_index_columns − 1 of every row hold indices.
Status CheckIndexColumns(const Eigen::MatrixXd& table, int num_index_columns,
                         const std::string& file) {
  for (Eigen::Index r = 0; r < table.rows(); ++r) {
    for (int j = 0; j < num_index_columns; ++j) {
      if (!IsIndex(table(r, j))) {
        return Status::Error(file + ": data row " + std::to_string(r + 1) +
                             ", column " + std::to_string(j + 1) +
                             ": not a non-negative integer index");
      }
    }
  }
  return Status::OK();
}

// Three finite coordinates, or three NaN (a point or frame left out of a
// reconstruction); the text reader has already refused ±Inf.
Status CheckCoordinates(const Eigen::Vector3d& x, const std::string& where) {
  if (x.allFinite() || x.array().isNaN().all()) return Status::OK();
  return Status::Error(
      where + ": coordinates are not finite (NaN in some but not all)");
}

// points_object.csv: F × P shapes, every (frame, point) exactly once.
Status ReadPointsObjectCsv(const std::string& file, int num_frames,
                           int num_points,
                           std::vector<Eigen::Matrix3Xd>* shapes) {
  Eigen::MatrixXd table;
  NRSFM_RETURN_IF_ERROR(
      ReadCsvTable(file, {"frame", "point", "x", "y", "z"}, &table));
  NRSFM_RETURN_IF_ERROR(CheckIndexColumns(table, 2, file));
  shapes->assign(num_frames, Eigen::Matrix3Xd::Constant(3, num_points, NAN));
  Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> seen =
      Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic>::Constant(
          num_frames, num_points, false);
  for (Eigen::Index r = 0; r < table.rows(); ++r) {
    const std::string where = file + ": data row " + std::to_string(r + 1);
    if (table(r, 0) >= num_frames || table(r, 1) >= num_points) {
      return Status::Error(where + ": frame or point index beyond the F = " +
                           std::to_string(num_frames) +
                           ", P = " + std::to_string(num_points) +
                           " of points_camera.csv");
    }
    const int t = static_cast<int>(table(r, 0));
    const int p = static_cast<int>(table(r, 1));
    if (seen(t, p))
      return Status::Error(where + ": frame " + std::to_string(t) + ", point " +
                           std::to_string(p) + " appears twice");
    seen(t, p) = true;
    const Eigen::Vector3d x = table.block<1, 3>(r, 2).transpose();
    NRSFM_RETURN_IF_ERROR(CheckCoordinates(x, where));
    (*shapes)[t].col(p) = x;
  }
  if (!seen.all()) {
    return Status::Error(file + ": has " + std::to_string(table.rows()) +
                         " rows; expected every frame and point of F = " +
                         std::to_string(num_frames) +
                         ", P = " + std::to_string(num_points) + " once");
  }
  return Status::OK();
}

// rotations.csv: one rotation per frame of `camera`.
Status ReadRotationsCsv(const std::string& file, int num_frames, int camera,
                        std::vector<Eigen::Matrix3d>* rotations) {
  Eigen::MatrixXd table;
  NRSFM_RETURN_IF_ERROR(ReadCsvTable(file,
                                     {"frame", "camera", "r11", "r12", "r13",
                                      "r21", "r22", "r23", "r31", "r32", "r33"},
                                     &table));
  NRSFM_RETURN_IF_ERROR(CheckIndexColumns(table, 2, file));
  rotations->assign(num_frames, Eigen::Matrix3d::Zero());
  std::vector<bool> seen(num_frames, false);
  for (Eigen::Index r = 0; r < table.rows(); ++r) {
    if (table(r, 1) != camera) continue;
    const std::string where = file + ": data row " + std::to_string(r + 1);
    if (table(r, 0) >= num_frames) {
      return Status::Error(
          where + ": frame index beyond the F = " + std::to_string(num_frames) +
          " of points_camera.csv");
    }
    const int t = static_cast<int>(table(r, 0));
    if (seen[t])
      return Status::Error(where + ": frame " + std::to_string(t) +
                           " appears twice");
    seen[t] = true;
    Eigen::Matrix3d rotation;
    for (int i = 0; i < 9; ++i) rotation(i / 3, i % 3) = table(r, 2 + i);
    // A frame left out of a reconstruction has a NaN rotation.
    const bool left_out = rotation.array().isNaN().all();
    if (!left_out &&
        (!rotation.allFinite() ||
         (rotation * rotation.transpose() - Eigen::Matrix3d::Identity())
                 .cwiseAbs()
                 .maxCoeff() > 1e-6 ||
         rotation.determinant() < 0.0)) {
      return Status::Error(where + ": not a rotation matrix");
    }
    (*rotations)[t] = rotation;
  }
  for (int t = 0; t < num_frames; ++t) {
    if (!seen[t]) {
      return Status::Error(file + ": no rotation of frame " +
                           std::to_string(t) + ", camera " +
                           std::to_string(camera));
    }
  }
  return Status::OK();
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
  NRSFM_RETURN_IF_ERROR(CheckIndexColumns(table, 3, file));
  long num_frames = 0, num_points = 0, rows_of_camera = 0;
  for (Eigen::Index r = 0; r < table.rows(); ++r) {
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
    NRSFM_RETURN_IF_ERROR(CheckCoordinates(x, where));
    result.points_in_camera[t].col(p) = x;
  }
  *truth = std::move(result);
  return Status::OK();
}

Status ReadResultShapes(const std::string& dir, int camera,
                        GroundTruth* shapes) {
  CHECK(shapes != nullptr);
  GroundTruth result;
  NRSFM_RETURN_IF_ERROR(ReadPointsCameraCsv(dir, camera, &result));
  const std::filesystem::path root(dir);
  NRSFM_RETURN_IF_ERROR(ReadPointsObjectCsv(
      (root / "points_object.csv").string(), result.NumFrames(),
      result.NumPoints(), &result.points_in_object));
  NRSFM_RETURN_IF_ERROR(ReadRotationsCsv((root / "rotations.csv").string(),
                                         result.NumFrames(), camera,
                                         &result.rotations));
  result.source = "result";
  *shapes = std::move(result);
  return Status::OK();
}

Status ReadPointsCovarianceCsv(const std::string& dir, int camera,
                               int num_frames, int num_points,
                               std::vector<Eigen::Matrix3d>* covariances) {
  const std::string file =
      (std::filesystem::path(dir) / "points_covariance.csv").string();
  Eigen::MatrixXd table;
  NRSFM_RETURN_IF_ERROR(ReadCsvTable(
      file, {"frame", "camera", "point", "xx", "xy", "xz", "yy", "yz", "zz"},
      &table));
  NRSFM_RETURN_IF_ERROR(CheckIndexColumns(table, 3, file));
  const Eigen::Matrix3d nan = Eigen::Matrix3d::Constant(NAN);
  std::vector<Eigen::Matrix3d> result(
      static_cast<size_t>(num_frames) * num_points, nan);
  std::vector<bool> seen(result.size(), false);
  for (Eigen::Index r = 0; r < table.rows(); ++r) {
    if (static_cast<int>(table(r, 1)) != camera) continue;
    const long t = static_cast<long>(table(r, 0));
    const long p = static_cast<long>(table(r, 2));
    const std::string where = file + ": row " + std::to_string(r + 1);
    if (t >= num_frames || p >= num_points) {
      return Status::Error(where + ": frame " + std::to_string(t) + ", point " +
                           std::to_string(p) + " outside the result's " +
                           std::to_string(num_frames) + " frames x " +
                           std::to_string(num_points) + " points");
    }
    const size_t i = static_cast<size_t>(t) * num_points + p;
    if (seen[i]) return Status::Error(where + ": (frame, point) appears twice");
    seen[i] = true;
    Eigen::Matrix3d& c = result[i];
    c << table(r, 3), table(r, 4), table(r, 5), table(r, 4), table(r, 6),
        table(r, 7), table(r, 5), table(r, 7), table(r, 8);
  }
  for (size_t i = 0; i < seen.size(); ++i) {
    if (!seen[i]) {
      return Status::Error(file + ": no row for frame " +
                           std::to_string(i / num_points) + ", point " +
                           std::to_string(i % num_points) + ", camera " +
                           std::to_string(camera));
    }
  }
  *covariances = std::move(result);
  return Status::OK();
}

Status ReadResultNumBases(const std::string& dir, int* num_bases) {
  const std::string path =
      (std::filesystem::path(dir) / "result.json").string();
  std::ifstream in(path);
  if (!in) return Status::Error(path + ": cannot open");
  const nlohmann::json json =
      nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (json.is_discarded() || !json.is_object())
    return Status::Error(path + ": not a JSON object");
  const auto it = json.find("num_bases");
  if (it == json.end() || !it->is_number_integer() ||
      it->get<long long>() < 1 || it->get<long long>() > 1000000) {
    return Status::Error(path + ": no integer num_bases >= 1");
  }
  *num_bases = static_cast<int>(it->get<long long>());
  return Status::OK();
}

Status ReadResultCamera(const std::string& dir, CameraModel* camera,
                        Eigen::Matrix4Xd* intrinsics) {
  *camera = CameraModel::kWeakPerspective;
  const std::filesystem::path file = std::filesystem::path(dir) / "result.json";
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) return Status::OK();
  std::ifstream in(file);
  const nlohmann::json json =
      nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (json.is_discarded() || !json.is_object()) {
    return Status::Error(file.string() + ": not a valid JSON object");
  }
  if (!json.contains("camera") || json["camera"] != "perspective") {
    return Status::OK();
  }
  const std::string what =
      file.string() +
      ": a perspective result needs \"intrinsics\", one row "
      "[fx, fy, cx, cy] (fx, fy > 0) per camera";
  if (!json.contains("intrinsics") || !json["intrinsics"].is_array() ||
      json["intrinsics"].empty()) {
    return Status::Error(what);
  }
  const nlohmann::json& rows = json["intrinsics"];
  Eigen::Matrix4Xd k(4, rows.size());
  for (size_t c = 0; c < rows.size(); ++c) {
    if (!rows[c].is_array() || rows[c].size() != 4) return Status::Error(what);
    for (int i = 0; i < 4; ++i) {
      if (!rows[c][i].is_number()) return Status::Error(what);
      k(i, c) = rows[c][i].get<double>();
    }
    if (!(k(0, c) > 0 && k(1, c) > 0) || !k.col(c).allFinite()) {
      return Status::Error(what);
    }
  }
  *camera = CameraModel::kPerspective;
  *intrinsics = std::move(k);
  return Status::OK();
}

}  // namespace nrsfm
