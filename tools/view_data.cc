#include "tools/view_data.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>

#include "core/eval/metrics.h"
#include "core/io/ground_truth.h"
#include "core/io/mat_io.h"
#include "core/io/read_measurements.h"
#include "core/io/result_reader.h"
#include "core/io/text_io.h"
#include "core/math/procrustes.h"
#include "core/model/measurements.h"
#include "problems/delaunay_edges.h"
#include "solvers/uncertainty/uncertainty.h"
#include "tools/flag_table.h"
#include "tools/reconstruction_steps.h"
#include "tools/view_frame_images.h"

namespace nrsfm {
namespace tools {
namespace {

namespace fs = std::filesystem;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string Str(int value) { return std::to_string(value); }

bool IsIndex(double value) {
  return value >= 0 && value < 2147483647.0 && value == std::floor(value);
}

// `x` minus the mean of its finite points (a point the reconstruction left
// out is NaN and stays so).
Eigen::Matrix3Xd Centred(const Eigen::Matrix3Xd& x) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int count = 0;
  for (Eigen::Index p = 0; p < x.cols(); ++p) {
    if (!x.col(p).allFinite()) continue;
    sum += x.col(p);
    ++count;
  }
  return x.colwise() -
         (count > 0 ? Eigen::Vector3d(sum / count) : Eigen::Vector3d::Zero());
}

// translations.csv (frame,camera,tx,ty,scale; frame,camera,tx,ty,tz for a
// perspective result): T_tc per view, 2 × FM (column tM + c). Sets
// *num_cameras to the largest camera index + 1.
Status ReadTranslations(const std::string& dir, int num_frames,
                        bool perspective, Eigen::Matrix2Xd* translations,
                        int* num_cameras) {
  const std::string file = (fs::path(dir) / "translations.csv").string();
  Eigen::MatrixXd table;
  NRSFM_RETURN_IF_ERROR(ReadCsvTable(
      file, {"frame", "camera", "tx", "ty", perspective ? "tz" : "scale"},
      &table));
  int cameras = 0;
  for (Eigen::Index r = 0; r < table.rows(); ++r) {
    for (int j = 0; j < 2; ++j) {
      if (!IsIndex(table(r, j))) {
        return Status::Error(file + ": data row " + std::to_string(r + 1) +
                             ", column " + Str(j + 1) +
                             ": not a non-negative integer index");
      }
    }
    if (table(r, 0) >= num_frames) {
      return Status::Error(file + ": data row " + std::to_string(r + 1) +
                           ": frame " + Str(static_cast<int>(table(r, 0))) +
                           " but points_camera.csv has F = " + Str(num_frames));
    }
    cameras = std::max(cameras, static_cast<int>(table(r, 1)) + 1);
  }
  if (static_cast<long>(table.rows()) !=
      static_cast<long>(num_frames) * cameras) {
    return Status::Error(
        file + ": " + std::to_string(table.rows()) + " rows, but F = " +
        Str(num_frames) + " frames x M = " + Str(cameras) + " cameras need " +
        std::to_string(static_cast<long>(num_frames) * cameras));
  }
  Eigen::Matrix2Xd result =
      Eigen::Matrix2Xd::Constant(2, num_frames * cameras, kNaN);
  std::vector<bool> seen(num_frames * cameras, false);
  for (Eigen::Index r = 0; r < table.rows(); ++r) {
    const int view =
        static_cast<int>(table(r, 0)) * cameras + static_cast<int>(table(r, 1));
    const std::string where = file + ": frame " +
                              Str(static_cast<int>(table(r, 0))) + ", camera " +
                              Str(static_cast<int>(table(r, 1)));
    if (seen[view]) return Status::Error(where + " appears twice");
    seen[view] = true;
    // A frame the reconstruction left out has nan, nan (result.json's
    // dropped_frames).
    const bool left_out = table.block<1, 2>(r, 2).array().isNaN().all();
    if (!left_out && !table.block<1, 2>(r, 2).allFinite()) {
      return Status::Error(where + ": tx, ty are not finite");
    }
    result.col(view) = table.block<1, 2>(r, 2).transpose();
  }
  *translations = std::move(result);
  *num_cameras = cameras;
  return Status::OK();
}

// The optional result.json: K, whether the solution is usable, the start and
// the warnings; its F, M, P must agree with the CSV files.
Status ReadResultJson(const std::string& dir, ViewData* data) {
  const fs::path file = fs::path(dir) / "result.json";
  std::error_code ec;
  if (!fs::exists(file, ec)) {
    data->notes.push_back("the result directory has no result.json");
    return Status::OK();
  }
  std::ifstream in(file);
  const nlohmann::json json =
      nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (json.is_discarded() || !json.is_object()) {
    return Status::Error(file.string() + ": not a valid JSON object");
  }
  const auto check = [&](const char* key, int expected) -> Status {
    if (json.contains(key) && json[key].is_number_integer() &&
        json[key].get<int>() != expected) {
      return Status::Error(file.string() + ": " + key + " = " +
                           Str(json[key].get<int>()) +
                           " but the CSV files have " + Str(expected));
    }
    return Status::OK();
  };
  NRSFM_RETURN_IF_ERROR(check("num_frames", data->num_frames));
  NRSFM_RETURN_IF_ERROR(check("num_cameras", data->num_cameras));
  NRSFM_RETURN_IF_ERROR(check("num_points", data->num_points));
  if (json.contains("num_bases") && json["num_bases"].is_number_integer()) {
    data->num_bases = json["num_bases"].get<int>();
  }
  if (json.contains("solution_usable") &&
      json["solution_usable"].is_boolean()) {
    data->solution_usable = json["solution_usable"].get<bool>();
  }
  if (json.contains("start_used") && json["start_used"].is_string()) {
    data->start_used = json["start_used"].get<std::string>();
  }
  if (json.contains("warnings") && json["warnings"].is_array()) {
    for (const auto& w : json["warnings"]) {
      if (w.is_string()) data->warnings.push_back(w.get<std::string>());
    }
  }
  return Status::OK();
}

bool IsMatFile(const std::string& path) {
  std::string extension = fs::path(path).extension().string();
  for (char& c : extension)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  std::error_code ec;
  return extension == ".mat" && fs::is_regular_file(path, ec);
}

// The skeleton edges of the motion-capture files: a variable `list`, n × 2,
// 1-based point indices (MATLAB). *found = false when the file has no such
// variable.
Status ReadSkeleton(const std::string& path, int num_points,
                    std::vector<std::array<int, 2>>* edges, bool* found) {
  *found = false;
  std::vector<std::string> names;
  NRSFM_RETURN_IF_ERROR(ListMatVariables(path, &names));
  if (std::find(names.begin(), names.end(), "list") == names.end())
    return Status::OK();
  Eigen::MatrixXd list;
  NRSFM_RETURN_IF_ERROR(ReadMatVariable(path, "list", &list));
  const std::string what =
      path + ": variable 'list' (skeleton edges, 1-based point indices)";
  if (list.rows() == 2 && list.cols() != 2) list.transposeInPlace();
  if (list.cols() != 2 || list.rows() == 0) {
    return Status::Error(what + " is " + std::to_string(list.rows()) + " x " +
                         std::to_string(list.cols()) + "; expected n x 2");
  }
  std::vector<std::array<int, 2>> result;
  for (Eigen::Index r = 0; r < list.rows(); ++r) {
    for (int j = 0; j < 2; ++j) {
      const double v = list(r, j);
      if (!(v >= 1 && v <= num_points && v == std::floor(v))) {
        std::ostringstream value;
        value << v;
        return Status::Error(what + ": row " + std::to_string(r + 1) +
                             " holds " + value.str() +
                             "; expected an integer in 1.." + Str(num_points));
      }
    }
    const int i = static_cast<int>(list(r, 0)) - 1,
              j = static_cast<int>(list(r, 1)) - 1;
    if (i != j) result.push_back({std::min(i, j), std::max(i, j)});
  }
  std::sort(result.begin(), result.end());
  result.erase(std::unique(result.begin(), result.end()), result.end());
  *edges = std::move(result);
  *found = true;
  return Status::OK();
}

// Scores the result against the truth as `nrsfm evaluate` does
// (core/eval/metrics.h EvaluateShapes: the object frame for S + Rs truth, the
// camera frame otherwise) and shows the shapes of that frame: the centred
// estimate, the truth mapped onto it by the e3D alignment, each frame's error;
// for a perspective result (fixed up to scale) by the alignment and one
// global scale, as e3d_scaled.
Status AddTruth(const ViewDataOptions& options, const GroundTruth& estimate,
                const GroundTruth& truth, bool perspective, ViewData* data) {
  NRSFM_RETURN_IF_ERROR(
      EvaluateShapes(truth, estimate, &data->metrics)
          .WithContext("--truth '" + options.truth_path + "'"));
  const EvaluationFrame frame = data->metrics.e3d_frame;
  data->scoring_frame =
      frame == EvaluationFrame::kObject
          ? "the object frame (points_object.csv against the world-frame S of "
            "the truth), "
            "as nrsfm evaluate scores it"
          : "camera 0's frame (points_camera.csv), as nrsfm evaluate scores it";
  if (perspective) {
    data->scoring_frame += " with one global scale (e3d_scaled)";
  }
  const std::vector<Eigen::Matrix3Xd>& shown = ScoredShapes(estimate, frame);
  const std::vector<Eigen::Matrix3Xd>& truth_shapes =
      ScoredShapes(truth, frame);
  // What the reconstruction left out (NaN) is not scored (EvaluateShapes):
  // the alignment and the errors are of the kept frames and points, each
  // frame centred on its kept points.
  const std::vector<int>& out_frames = data->metrics.unscored_frames;
  const std::vector<int>& out_points = data->metrics.unscored_points;
  std::vector<int> kept_points;
  for (int p = 0; p < data->num_points; ++p) {
    if (!std::binary_search(out_points.begin(), out_points.end(), p))
      kept_points.push_back(p);
  }
  std::vector<Eigen::Matrix3Xd> kept_truth, kept_shown;
  for (int t = 0; t < data->num_frames; ++t) {
    if (std::binary_search(out_frames.begin(), out_frames.end(), t)) continue;
    kept_truth.push_back(truth_shapes[t](Eigen::all, kept_points));
    kept_shown.push_back(shown[t](Eigen::all, kept_points));
  }
  const E3DDetail detail = ComputeE3DDetail(kept_truth, kept_shown,
                                            /*with_scale=*/perspective);
  const auto centred =
      [&kept_points](const Eigen::Matrix3Xd& x) -> Eigen::Matrix3Xd {
    const Eigen::Vector3d mean = x(Eigen::all, kept_points).rowwise().mean();
    return x.colwise() - mean;
  };
  data->estimate.clear();
  data->truth_aligned.clear();
  data->frame_error = Eigen::VectorXd::Constant(data->num_frames, kNaN);
  for (int t = 0, k = 0; t < data->num_frames; ++t) {
    data->estimate.push_back(centred(shown[t]));
    // Y is orthogonal: ||X − c Y X̂|| = c ||Yᵀ X / c − X̂||; the page shows
    // the truth in the estimate's frame and scale.
    data->truth_aligned.push_back(detail.alignment.transpose() *
                                  centred(truth_shapes[t]) /
                                  detail.estimate_scale);
    if (!std::binary_search(out_frames.begin(), out_frames.end(), t)) {
      data->frame_error(t) = detail.frame_errors[k++];
    }
  }
  data->has_truth = true;
  return Status::OK();
}

Status AddTracks(const ViewDataOptions& options, const std::string& result_dir,
                 Measurements* measurements, ViewData* data) {
  InputOptions input_options = options.input;
  input_options.num_cameras = data->num_cameras;
  InputDetails details;
  NRSFM_RETURN_IF_ERROR(ReadMeasurements(options.input_path, input_options,
                                         measurements, &details));
  for (const std::string& warning : details.warnings) {
    data->notes.push_back(options.input_path + ": " + warning);
  }
  const Measurements& m = *measurements;
  if (m.num_frames != data->num_frames || m.num_cameras != data->num_cameras ||
      m.num_points != data->num_points) {
    return Status::Error(
        "--input '" + options.input_path + "' has F = " + Str(m.num_frames) +
        ", M = " + Str(m.num_cameras) + ", P = " + Str(m.num_points) +
        " but the result '" + result_dir +
        "' has F = " + Str(data->num_frames) +
        ", M = " + Str(data->num_cameras) + ", P = " + Str(data->num_points));
  }
  data->tracks = m.W;
  // A point or frame the reconstruction left out has no reprojection: it is
  // not scored.
  Measurements scored = m;
  for (int view = 0; view < m.NumViews(); ++view) {
    for (int p = 0; p < m.num_points; ++p) {
      if (!m.visible(view, p)) {
        data->tracks.block<2, 1>(2 * view, p).setConstant(kNaN);
      } else if (data->reprojection.block<2, 1>(2 * view, p)
                     .array()
                     .isNaN()
                     .any()) {
        scored.visible(view, p) = false;
      }
    }
  }
  const FrameReprojectionRms rms =
      ComputeFrameReprojectionRms(scored, data->reprojection);
  data->frame_reprojection_rms = rms.frame_rms;
  data->reprojection_rms = rms.rms;
  data->has_tracks = true;
  return Status::OK();
}

// Skeleton `list` of the truth, else of the input, else the Delaunay edges
// of the reference view (problems/delaunay_edges.h) of the tracks, or of the
// reprojections when no tracks were given.
Status AddEdges(const ViewDataOptions& options, const Measurements* tracks,
                ViewData* data) {
  for (const std::string& path : {options.truth_path, options.input_path}) {
    if (path.empty() || !IsMatFile(path)) continue;
    bool found = false;
    NRSFM_RETURN_IF_ERROR(
        ReadSkeleton(path, data->num_points, &data->edges, &found));
    if (found) {
      data->edge_source = "the skeleton 'list' of " + path;
      return Status::OK();
    }
  }
  Measurements reprojected;
  const Measurements* measurements = tracks;
  if (measurements == nullptr) {
    reprojected.num_frames = data->num_frames;
    reprojected.num_cameras = data->num_cameras;
    reprojected.num_points = data->num_points;
    reprojected.W = data->reprojection;
    reprojected.visible = VisibilityMask::Constant(reprojected.NumViews(),
                                                   data->num_points, true);
    measurements = &reprojected;
  }
  std::vector<NeighbourEdge> edges;
  int reference_frame = -1;
  const Status status = ComputeDelaunayEdges(
      *measurements, DelaunayEdgesOptions(), &edges, &reference_frame);
  if (!status.ok()) {
    data->edges.clear();
    data->edge_source = "none";
    data->notes.push_back("no edges drawn: " + status.message());
    return Status::OK();
  }
  data->edges.clear();
  for (const NeighbourEdge& e : edges) data->edges.push_back({e.i, e.j});
  data->edge_source = "Delaunay triangulation of frame " +
                      Str(reference_frame) + " (camera 0) of the " +
                      (tracks != nullptr ? "2D tracks" : "reprojected points") +
                      ", as the smoothness term builds it";
  return Status::OK();
}

}  // namespace

Status GatherViewData(const ViewDataOptions& options, ViewData* data) {
  const std::string& dir = options.result_dir;
  std::error_code ec;
  if (!fs::exists(dir, ec))
    return Status::Error("--result '" + dir + "': no such directory");
  if (!fs::is_directory(dir, ec)) {
    return Status::Error("--result '" + dir +
                         "' is not a directory (a result of nrsfm "
                         "reconstruct)");
  }
  ViewData result;

  // Camera-frame points of every camera and the translations: the
  // reprojections w_tcp = Π X_tc[:, p] + T_tc (core/io/result_writer.h), or
  // for a perspective result (core/model/model.h) the pinhole projection
  // (fx x / z + cx, fy y / z + cy) of X_tc, which holds the translation.
  GroundTruth camera0;
  NRSFM_RETURN_IF_ERROR(ReadPointsCameraCsv(dir, 0, &camera0));
  result.num_frames = camera0.NumFrames();
  result.num_points = camera0.NumPoints();
  Eigen::Matrix4Xd intrinsics;
  NRSFM_RETURN_IF_ERROR(
      ReadResultCamera(dir, &result.camera_model, &intrinsics));
  const bool perspective = result.camera_model == CameraModel::kPerspective;
  Eigen::Matrix2Xd translations;
  NRSFM_RETURN_IF_ERROR(ReadTranslations(dir, result.num_frames, perspective,
                                         &translations, &result.num_cameras));
  const int f = result.num_frames, m = result.num_cameras,
            p = result.num_points;
  if (perspective && intrinsics.cols() != m) {
    return Status::Error(
        dir + "/result.json: " + Str(static_cast<int>(intrinsics.cols())) +
        " rows of intrinsics but translations.csv has M = " + Str(m) +
        " cameras");
  }
  result.reprojection.resize(2 * f * m, p);
  for (int c = 0; c < m; ++c) {
    GroundTruth camera = camera0;
    if (c > 0) {
      NRSFM_RETURN_IF_ERROR(ReadPointsCameraCsv(dir, c, &camera));
      if (camera.NumFrames() != f || camera.NumPoints() != p) {
        return Status::Error(dir + "/points_camera.csv: camera " + Str(c) +
                             " has F = " + Str(camera.NumFrames()) +
                             ", P = " + Str(camera.NumPoints()) +
                             " but camera 0 has F = " + Str(f) +
                             ", P = " + Str(p));
      }
    }
    for (int t = 0; t < f; ++t) {
      const Eigen::Matrix3Xd& x = camera.points_in_camera[t];
      auto w = result.reprojection.block(2 * (t * m + c), 0, 2, p);
      if (perspective) {
        const Eigen::Vector4d k = intrinsics.col(c);
        w.row(0) = (k(0) * x.row(0).cwiseQuotient(x.row(2))).array() + k(2);
        w.row(1) = (k(1) * x.row(1).cwiseQuotient(x.row(2))).array() + k(3);
      } else {
        w = x.topRows<2>().colwise() + translations.col(t * m + c);
      }
    }
  }
  NRSFM_RETURN_IF_ERROR(ReadResultJson(dir, &result));
  if (fs::exists(fs::path(dir) / "points_covariance.csv", ec)) {
    std::vector<Eigen::Matrix3d> covariances;
    NRSFM_RETURN_IF_ERROR(
        ReadPointsCovarianceCsv(dir, /*camera=*/0, f, p, &covariances));
    result.point_std.resize(f * p);
    for (int i = 0; i < f * p; ++i) {
      const double variance = covariances[i].trace();  // NaN: left out
      if (variance < 0.0 || std::isinf(variance)) {
        return Status::Error(dir + "/points_covariance.csv: frame " +
                             Str(i / p) + ", point " + Str(i % p) +
                             ": the variances xx + yy + zz are not a "
                             "non-negative number");
      }
      result.point_std(i) =
          std::isnan(variance) ? kNaN : PointStd(covariances[i]);
    }
    result.has_uncertainty = true;
  }

  GroundTruth truth;
  if (!options.truth_path.empty()) {
    NRSFM_RETURN_IF_ERROR(
        ReadTruth(options.truth_path, options.truth_variable, &truth));
    if (truth.NumFrames() != f || truth.NumPoints() != p) {
      return Status::Error("--truth '" + options.truth_path +
                           "' has F = " + Str(truth.NumFrames()) + ", P = " +
                           Str(truth.NumPoints()) + " but the result '" + dir +
                           "' has F = " + Str(f) + ", P = " + Str(p));
    }
  }
  // Without a truth the camera frame is shown; with one, the frame it is
  // scored in (AddTruth).
  result.scoring_frame = "camera 0's frame (points_camera.csv)";
  for (const Eigen::Matrix3Xd& x : camera0.points_in_camera)
    result.estimate.push_back(Centred(x));
  if (!options.truth_path.empty()) {
    GroundTruth estimate = camera0;
    if (truth.HasObjectFrame()) {
      NRSFM_RETURN_IF_ERROR(ReadResultShapes(dir, /*camera=*/0, &estimate));
    }
    NRSFM_RETURN_IF_ERROR(
        AddTruth(options, estimate, truth, perspective, &result));
  } else {
    result.notes.push_back("no ground truth given (--truth): no error shown");
  }

  Measurements tracks;
  if (!options.input_path.empty()) {
    NRSFM_RETURN_IF_ERROR(AddTracks(options, dir, &tracks, &result));
  } else {
    result.notes.push_back(
        "the 2D tracks were not given (--input): the 2D view shows the "
        "reprojections only");
  }
  NRSFM_RETURN_IF_ERROR(AddEdges(
      options, options.input_path.empty() ? nullptr : &tracks, &result));
  if (!options.frames_dir.empty()) {
    NRSFM_RETURN_IF_ERROR(AddFrameImages(options, &result));
  }
  *data = std::move(result);
  return Status::OK();
}

}  // namespace tools
}  // namespace nrsfm
