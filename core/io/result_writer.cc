#include "core/io/result_writer.h"

#include <glog/logging.h>
#include <matio.h>

#include <Eigen/Core>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>
#include <system_error>

#include "core/io/text_io.h"
#include "core/math/parallel_for.h"

namespace nrsfm {
namespace {

namespace fs = std::filesystem;

void PrintXyz(TextWriter* out, const Eigen::Vector3d& x) {
  out->Char(',').Number(x(0)).Char(',').Number(x(1)).Char(',').Number(x(2));
  out->Char('\n');
}

Status WritePointsCamera(const fs::path& dir, const Model& model) {
  TextWriter out;
  NRSFM_RETURN_IF_ERROR(out.Open((dir / "points_camera.csv").string()));
  out.Text("frame,camera,point,x,y,z\n");
  for (int t = 0; t < model.num_frames; ++t) {
    for (int c = 0; c < model.num_cameras; ++c) {
      const Eigen::Matrix3Xd points = model.ShapeInCamera(t, c);
      for (int p = 0; p < model.num_points; ++p) {
        out.Int(t).Char(',').Int(c).Char(',').Int(p);
        PrintXyz(&out, points.col(p));
      }
    }
  }
  return out.Close();
}

void PrintCovariance(TextWriter* out, const Eigen::Matrix3d& c) {
  out->Char(',').Number(c(0, 0)).Char(',').Number(c(0, 1)).Char(',');
  out->Number(c(0, 2)).Char(',').Number(c(1, 1)).Char(',');
  out->Number(c(1, 2)).Char(',').Number(c(2, 2)).Char('\n');
}

Status WritePointsObject(const fs::path& dir, const Model& model) {
  TextWriter out;
  NRSFM_RETURN_IF_ERROR(out.Open((dir / "points_object.csv").string()));
  out.Text("frame,point,x,y,z\n");
  for (int t = 0; t < model.num_frames; ++t) {
    const Eigen::Matrix3Xd shape = model.ShapeInObject(t);
    for (int p = 0; p < model.num_points; ++p) {
      out.Int(t).Char(',').Int(p);
      PrintXyz(&out, shape.col(p));
    }
  }
  return out.Close();
}

Status WriteViews(const fs::path& dir, const Model& model) {
  TextWriter rotations, translations;
  NRSFM_RETURN_IF_ERROR(rotations.Open((dir / "rotations.csv").string()));
  NRSFM_RETURN_IF_ERROR(translations.Open((dir / "translations.csv").string()));
  rotations.Text("frame,camera,r11,r12,r13,r21,r22,r23,r31,r32,r33\n");
  const bool perspective = model.camera == CameraModel::kPerspective;
  translations.Text(perspective ? "frame,camera,tx,ty,tz\n"
                                : "frame,camera,tx,ty,scale\n");
  for (int t = 0; t < model.num_frames; ++t) {
    for (int c = 0; c < model.num_cameras; ++c) {
      const Eigen::Matrix3d r = model.Rotation(t, c);
      rotations.Int(t).Char(',').Int(c);
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) rotations.Char(',').Number(r(i, j));
      }
      rotations.Char('\n');
      const int view = model.View(t, c);
      translations.Int(t).Char(',').Int(c).Char(',');
      translations.Number(model.translations(0, view)).Char(',');
      translations.Number(model.translations(1, view)).Char(',');
      translations.Number(perspective ? model.depths(view) : model.scales(view))
          .Char('\n');
    }
  }
  NRSFM_RETURN_IF_ERROR(rotations.Close());
  return translations.Close();
}

Status WriteWeightsAndBasis(const fs::path& dir, const Model& model) {
  TextWriter weights, basis;
  NRSFM_RETURN_IF_ERROR(weights.Open((dir / "weights.csv").string()));
  NRSFM_RETURN_IF_ERROR(basis.Open((dir / "basis.csv").string()));
  weights.Text("frame");
  for (int k = 0; k < model.num_bases; ++k) weights.Text(",l").Int(k + 1);
  weights.Char('\n');
  for (int t = 0; t < model.num_frames; ++t) {
    weights.Int(t);
    for (int k = 0; k < model.num_bases; ++k) {
      weights.Char(',').Number(model.weights(k, t));
    }
    weights.Char('\n');
  }
  basis.Text("k,point,x,y,z\n");
  for (int k = 0; k < model.num_bases; ++k) {
    for (int p = 0; p < model.num_points; ++p) {
      basis.Int(k).Char(',').Int(p);
      PrintXyz(&basis, model.basis.block<3, 1>(3 * k, p));
    }
  }
  NRSFM_RETURN_IF_ERROR(weights.Close());
  return basis.Close();
}

Status WritePly(const fs::path& dir, const Model& model) {
  const fs::path ply_dir = dir / "ply";
  std::error_code ec;
  if (!fs::create_directory(ply_dir, ec)) {
    return Status::Error(ply_dir.string() +
                         ": cannot create the directory: " + ec.message());
  }
  for (int t = 0; t < model.num_frames; ++t) {
    char name[32];
    std::snprintf(name, sizeof(name), "frame_%05d.ply", t);
    TextWriter out;
    NRSFM_RETURN_IF_ERROR(out.Open((ply_dir / name).string()));
    out.Text("ply\nformat ascii 1.0\ncomment nrsfm frame ")
        .Int(t)
        .Text(" in the frame of camera 0\nelement vertex ")
        .Int(model.num_points)
        .Text(
            "\nproperty double x\nproperty double y\nproperty double z\n"
            "end_header\n");
    const Eigen::Matrix3Xd points = model.ShapeInCamera(t, 0);
    for (int p = 0; p < model.num_points; ++p) {
      out.Number(points(0, p)).Char(' ').Number(points(1, p)).Char(' ');
      out.Number(points(2, p)).Char('\n');
    }
    NRSFM_RETURN_IF_ERROR(out.Close());
  }
  return Status::OK();
}

}  // namespace

std::string ReconstructionJson(const Measurements& measurements,
                               const Model& model,
                               const ReconstructionReport& report) {
  using Json = nlohmann::ordered_json;
  Json json;
  json["input"] = report.input;
  json["num_frames"] = model.num_frames;
  json["num_cameras"] = model.num_cameras;
  json["num_points"] = model.num_points;
  json["num_bases"] = model.num_bases;
  json["num_visible"] = measurements.NumVisible();
  json["camera"] = CameraModelName(model.camera);
  if (model.camera == CameraModel::kPerspective) {
    // (fx, fy, cx, cy) per camera, pixels: u = fx x / z + cx, v = fy y / z +
    // cy.
    Json intrinsics = Json::array();
    for (int c = 0; c < model.num_cameras; ++c) {
      intrinsics.push_back({model.intrinsics(0, c), model.intrinsics(1, c),
                            model.intrinsics(2, c), model.intrinsics(3, c)});
    }
    json["intrinsics"] = intrinsics;
  }
  // The input's index of each frame and point when the reader renumbered
  // them (a sparse observation list, core/io/text_io.h).
  if (!measurements.frame_ids.empty())
    json["input_frames"] = measurements.frame_ids;
  if (!measurements.point_ids.empty())
    json["input_points"] = measurements.point_ids;
  Json options = Json::object();
  for (const auto& [key, value] : report.options) options[key] = value;
  json["options"] = options;
  json["start_used"] = report.start_used;
  json["start_reprojection_rms"] = report.start_reprojection_rms;
  Json stages = Json::array();
  for (const StageReport& stage : report.stages) {
    stages.push_back({{"name", stage.name},
                      {"initial_cost", stage.initial_cost},
                      {"final_cost", stage.final_cost},
                      {"iterations", stage.iterations},
                      {"seconds", stage.seconds}});
  }
  json["stages"] = stages;
  json["reprojection_rms"] = report.reprojection_rms;
  json["solution_usable"] = report.solution_usable;
  json["warnings"] = report.warnings;
  json["dropped_points"] = report.dropped_points;
  json["dropped_frames"] = report.dropped_frames;
  Json term_weights = Json::object();
  for (const auto& [name, value] : report.term_weights)
    term_weights[name] = value;
  json["term_weights"] = term_weights;
  Json diagnostics = Json::object();
  for (const auto& [name, value] : report.diagnostics)
    diagnostics[name] = value;
  json["diagnostics"] = diagnostics;
  Json metrics = Json::object();
  for (const auto& [name, value] : report.metrics) metrics[name] = value;
  if (!report.e3d_frame.empty()) metrics["e3d_frame"] = report.e3d_frame;
  json["metrics"] = metrics;
  Json versions = Json::object();
  for (const auto& [name, value] : report.versions) versions[name] = value;
  versions["eigen"] = std::to_string(EIGEN_WORLD_VERSION) + "." +
                      std::to_string(EIGEN_MAJOR_VERSION) + "." +
                      std::to_string(EIGEN_MINOR_VERSION);
  versions["matio"] = MATIO_VERSION_STR;
  versions["nlohmann_json"] = std::to_string(NLOHMANN_JSON_VERSION_MAJOR) +
                              "." +
                              std::to_string(NLOHMANN_JSON_VERSION_MINOR) +
                              "." + std::to_string(NLOHMANN_JSON_VERSION_PATCH);
  json["versions"] = versions;
  // Invalid UTF-8 (e.g. in a path) is replaced instead of throwing.
  return json.dump(2, ' ', false, Json::error_handler_t::replace);
}

namespace {

Status WriteJson(const fs::path& dir, const Measurements& measurements,
                 const Model& model, const ReconstructionReport& report) {
  TextWriter out;
  NRSFM_RETURN_IF_ERROR(out.Open((dir / "result.json").string()));
  out.Text(ReconstructionJson(measurements, model, report)).Char('\n');
  return out.Close();
}

Status WriteAll(const fs::path& dir, const Measurements& measurements,
                const Model& model, const ReconstructionReport& report,
                const WriteOptions& options) {
  // The points files are most of the bytes: one per thread.
  Status points[2];
  ParallelFor(2, options.num_threads, 1, [&](int begin, int end) {
    for (int i = begin; i < end; ++i) {
      points[i] = i == 0 ? WritePointsCamera(dir, model)
                         : WritePointsObject(dir, model);
    }
  });
  for (const Status& status : points) NRSFM_RETURN_IF_ERROR(status);
  NRSFM_RETURN_IF_ERROR(WriteViews(dir, model));
  NRSFM_RETURN_IF_ERROR(WriteWeightsAndBasis(dir, model));
  if (options.write_ply) NRSFM_RETURN_IF_ERROR(WritePly(dir, model));
  return WriteJson(dir, measurements, model, report);
}

// A new, empty directory `parent/.<name>.<tag>-NNNNNNNN` (mode from umask).
Status MakeSiblingDir(const fs::path& parent, const std::string& name,
                      const char* tag, fs::path* created) {
  std::random_device random;
  std::error_code ec;
  for (int attempt = 0; attempt < 100; ++attempt) {
    char suffix[16];
    std::snprintf(suffix, sizeof(suffix), "%08x",
                  static_cast<unsigned>(random()));
    const fs::path candidate = parent / ("." + name + "." + tag + "-" + suffix);
    if (fs::create_directory(candidate, ec)) {
      *created = candidate;
      return Status::OK();
    }
    if (ec) break;
  }
  return Status::Error(parent.string() + ": cannot create a directory there" +
                       (ec ? ": " + ec.message() : std::string()));
}

// Checks whether `target` may be (re)placed; sets *exists.
Status CheckTarget(const fs::path& target, bool overwrite, bool* exists) {
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(target, ec);
  *exists = fs::exists(status);
  if (!*exists) return Status::OK();
  if (!fs::is_directory(status)) {
    return Status::Error(target.string() + ": exists and is not a directory");
  }
  const bool empty = fs::is_empty(target, ec);
  if (ec)
    return Status::Error(target.string() +
                         ": cannot read the directory: " + ec.message());
  if (empty) return Status::OK();
  if (!overwrite) {
    return Status::Error(target.string() +
                         ": the output directory exists and is not empty "
                         "(allow overwriting to replace it)");
  }
  if (!fs::exists(target / "result.json", ec)) {
    return Status::Error(
        target.string() +
        ": the output directory is not empty and holds no result.json, so it "
        "is not an earlier result; refusing to replace it");
  }
  return Status::OK();
}

// Renames the finished `staging` directory to `target`, replacing an
// existing target (moved aside first, removed after the swap).
Status MoveIntoPlace(const fs::path& staging, const fs::path& target,
                     bool target_exists) {
  std::error_code ec;
  if (target_exists && fs::is_empty(target, ec)) {
    fs::remove(target, ec);
    target_exists = false;
  }
  fs::path old;
  if (target_exists) {
    NRSFM_RETURN_IF_ERROR(MakeSiblingDir(
        target.parent_path(), target.filename().string(), "old", &old));
    fs::rename(target, old, ec);  // replaces the empty directory `old`
    if (ec) {
      fs::remove(old, ec);
      return Status::Error(
          target.string() +
          ": cannot move the old result aside: " + ec.message());
    }
  }
  fs::rename(staging, target, ec);
  if (ec) {
    const std::string message = ec.message();
    if (target_exists) fs::rename(old, target, ec);
    return Status::Error(target.string() +
                         ": cannot move the result into place: " + message);
  }
  if (target_exists) fs::remove_all(old, ec);
  return Status::OK();
}

}  // namespace

Status WriteReconstruction(const std::string& dir,
                           const Measurements& measurements, const Model& model,
                           const ReconstructionReport& report,
                           const WriteOptions& options) {
  const bool dropped =
      !report.dropped_points.empty() || !report.dropped_frames.empty();
  NRSFM_RETURN_IF_ERROR(model.Validate(/*allow_nan=*/dropped)
                            .WithContext("WriteReconstruction: model"));
  if (measurements.num_frames != model.num_frames ||
      measurements.num_cameras != model.num_cameras ||
      measurements.num_points != model.num_points) {
    return Status::Error(
        "WriteReconstruction: the measurements (F = " +
        std::to_string(measurements.num_frames) +
        ", M = " + std::to_string(measurements.num_cameras) +
        ", P = " + std::to_string(measurements.num_points) +
        ") do not match the model (F = " + std::to_string(model.num_frames) +
        ", M = " + std::to_string(model.num_cameras) +
        ", P = " + std::to_string(model.num_points) + ")");
  }
  if (dir.empty())
    return Status::Error("WriteReconstruction: empty output directory name");
  std::error_code ec;
  fs::path target = fs::absolute(dir, ec).lexically_normal();
  if (ec)
    return Status::Error(dir + ": invalid output directory: " + ec.message());
  if (target.filename().empty()) target = target.parent_path();
  const std::string name = target.filename().string();
  if (name.empty() || name == "." || name == ".." ||
      target == target.root_path()) {
    return Status::Error(dir + ": not usable as an output directory");
  }
  bool exists = false;
  NRSFM_RETURN_IF_ERROR(CheckTarget(target, options.overwrite, &exists));

  const fs::path parent = target.parent_path();
  fs::create_directories(parent, ec);
  if (ec) {
    return Status::Error(parent.string() +
                         ": cannot create the directory: " + ec.message());
  }
  fs::path staging;
  NRSFM_RETURN_IF_ERROR(MakeSiblingDir(parent, name, "tmp", &staging));
  Status status = WriteAll(staging, measurements, model, report, options);
  if (status.ok()) status = MoveIntoPlace(staging, target, exists);
  if (!status.ok()) fs::remove_all(staging, ec);
  return status;
}

Status WriteCovariances(const std::string& dir, int num_frames, int num_cameras,
                        int num_points,
                        const std::vector<Eigen::Matrix3d>& points,
                        const std::vector<Eigen::Matrix3d>& rotations) {
  const size_t views = static_cast<size_t>(num_frames) * num_cameras;
  CHECK_EQ(points.size(), views * num_points);
  CHECK_EQ(rotations.size(), views);
  TextWriter out;
  NRSFM_RETURN_IF_ERROR(
      out.Open((fs::path(dir) / "points_covariance.csv").string()));
  out.Text("frame,camera,point,xx,xy,xz,yy,yz,zz\n");
  for (int t = 0; t < num_frames; ++t) {
    for (int c = 0; c < num_cameras; ++c) {
      for (int p = 0; p < num_points; ++p) {
        out.Int(t).Char(',').Int(c).Char(',').Int(p);
        PrintCovariance(
            &out,
            points[(static_cast<size_t>(t) * num_cameras + c) * num_points +
                   p]);
      }
    }
  }
  NRSFM_RETURN_IF_ERROR(out.Close());
  TextWriter rotation_out;
  NRSFM_RETURN_IF_ERROR(
      rotation_out.Open((fs::path(dir) / "rotations_covariance.csv").string()));
  rotation_out.Text("frame,camera,xx,xy,xz,yy,yz,zz\n");
  for (int t = 0; t < num_frames; ++t) {
    for (int c = 0; c < num_cameras; ++c) {
      rotation_out.Int(t).Char(',').Int(c);
      PrintCovariance(&rotation_out,
                      rotations[static_cast<size_t>(t) * num_cameras + c]);
    }
  }
  return rotation_out.Close();
}

}  // namespace nrsfm
