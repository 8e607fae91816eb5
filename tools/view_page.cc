#include "tools/view_page.h"

#include <glog/logging.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string_view>

#include "tools/viewer_assets.h"

namespace nrsfm {
namespace tools {
namespace {

namespace fs = std::filesystem;

constexpr char kScriptsMarker[] = "<!-- NRSFM_SCRIPTS -->";

// Appends `value` with `digits` significant digits, "null" for NaN.
void AppendNumber(double value, int digits, std::string* out) {
  if (!std::isfinite(value)) {
    out->append("null");
    return;
  }
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.*g", digits, value);
  out->append(buffer);
}

// A JSON array of the values in order, e.g. [1.5,null,2].
template <typename Visit>
std::string NumberArray(Visit visit) {
  std::string out = "[";
  bool first = true;
  visit([&](double value, int digits) {
    if (!first) out.push_back(',');
    first = false;
    AppendNumber(value, digits, &out);
  });
  out.push_back(']');
  return out;
}

std::string Shapes(const std::vector<Eigen::Matrix3Xd>& shapes) {
  return NumberArray([&](auto emit) {
    for (const Eigen::Matrix3Xd& x : shapes) {
      for (Eigen::Index p = 0; p < x.cols(); ++p) {
        for (int i = 0; i < 3; ++i) emit(x(i, p), 7);
      }
    }
  });
}

// A (2FM) × P matrix as F·M·P (u, v) pairs, frame-major.
std::string Tracks(const Eigen::MatrixXd& w) {
  return NumberArray([&](auto emit) {
    for (Eigen::Index view = 0; view < w.rows() / 2; ++view) {
      for (Eigen::Index p = 0; p < w.cols(); ++p) {
        emit(w(2 * view, p), 7);
        emit(w(2 * view + 1, p), 7);
      }
    }
  });
}

std::string Vector(const Eigen::VectorXd& v) {
  return NumberArray([&](auto emit) {
    for (Eigen::Index i = 0; i < v.size(); ++i) emit(v(i), 10);
  });
}

// JSON that is safe inside a <script> element: '<' only occurs in strings,
// where \u003c means the same, so no "</script>" or "<!--" can appear.
std::string ScriptSafe(const std::string& json) {
  std::string out;
  out.reserve(json.size());
  for (char c : json) {
    if (c == '<') {
      out += "\\u003c";
    } else {
      out.push_back(c);
    }
  }
  return out;
}

std::string DataJson(const ViewData& data, const ViewPageSources& sources) {
  nlohmann::ordered_json meta;
  meta["num_frames"] = data.num_frames;
  meta["num_cameras"] = data.num_cameras;
  meta["num_points"] = data.num_points;
  meta["num_bases"] = data.num_bases;
  meta["result"] = sources.result_dir;
  meta["truth"] = sources.truth_path;
  meta["input"] = sources.input_path;
  meta["scoring_frame"] = data.scoring_frame;
  meta["camera_model"] = CameraModelName(data.camera_model);
  meta["has_truth"] = data.has_truth;
  meta["has_tracks"] = data.has_tracks;
  meta["has_uncertainty"] = data.has_uncertainty;
  if (data.has_truth) {
    nlohmann::ordered_json metrics;
    for (const auto& [name, value] : MetricList(data.metrics))
      metrics[name] = value;
    metrics["e3d_frame"] = EvaluationFrameName(data.metrics.e3d_frame);
    meta["metrics"] = metrics;
  }
  if (data.has_tracks) {
    if (std::isfinite(data.reprojection_rms)) {
      meta["reprojection_rms"] = data.reprojection_rms;
    } else {
      meta["reprojection_rms"] = nullptr;
    }
  }
  meta["edge_source"] = data.edge_source;
  meta["solution_usable"] = data.solution_usable;
  meta["start_used"] = data.start_used;
  meta["warnings"] = data.warnings;
  meta["notes"] = data.notes;

  std::string json = "{\"meta\":" + ScriptSafe(meta.dump());
  json += ",\n\"estimate\":" + Shapes(data.estimate);
  json +=
      ",\n\"truth\":" + (data.has_truth ? Shapes(data.truth_aligned) : "null");
  json += ",\n\"frame_error\":" +
          (data.has_truth ? Vector(data.frame_error) : "null");
  json += ",\n\"point_std\":" +
          (data.has_uncertainty ? Vector(data.point_std) : "null");
  json += ",\n\"reprojection\":" + Tracks(data.reprojection);
  json += ",\n\"tracks\":" + (data.has_tracks ? Tracks(data.tracks) : "null");
  // The frames' data: URLs hold only base64 characters and the prefix.
  json += ",\n\"frames\":";
  if (data.frame_images.empty()) {
    json += "null";
  } else {
    json += "[";
    for (std::size_t t = 0; t < data.frame_images.size(); ++t) {
      json += (t > 0 ? ",\"" : "\"") + data.frame_images[t] + "\"";
    }
    json += "]";
  }
  json += ",\n\"frame_reprojection_rms\":" +
          (data.has_tracks ? Vector(data.frame_reprojection_rms) : "null");
  json += ",\n\"edges\":[";
  for (size_t e = 0; e < data.edges.size(); ++e) {
    if (e > 0) json.push_back(',');
    json += "[" + std::to_string(data.edges[e][0]) + "," +
            std::to_string(data.edges[e][1]) + "]";
  }
  json += "]}";
  return json;
}

std::string Lowercase(std::string s) {
  for (char& c : s)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

std::string RenderViewerPage(const ViewData& data,
                             const ViewPageSources& sources) {
  const std::string_view page(kViewerPageHtml, kViewerPageHtmlSize);
  const size_t marker = page.find(kScriptsMarker);
  CHECK_NE(marker, std::string_view::npos)
      << "tools/viewer/page.html lacks " << kScriptsMarker;
  std::string html;
  html.reserve(kThreeJsSize + kOrbitControlsJsSize +
               8 * data.num_frames * data.num_points * 12 + page.size() +
               kViewerJsSize);
  html.append(page.substr(0, marker));
  html +=
      "<script>\n/* three.js r111, Copyright 2010-2019 three.js authors, MIT "
      "License;\n"
      "   Debian's libjs-three: three.min.js and "
      "examples/js/controls/OrbitControls.js */\n";
  html.append(kThreeJs, kThreeJsSize);
  html += "\n</script>\n<script>\n";
  html.append(kOrbitControlsJs, kOrbitControlsJsSize);
  html += "\n</script>\n<script id=\"nrsfm-data\" type=\"application/json\">\n";
  html += DataJson(data, sources);
  html += "\n</script>\n<script>\n";
  html.append(kViewerJs, kViewerJsSize);
  html += "\n</script>";
  html.append(page.substr(marker + std::strlen(kScriptsMarker)));
  return html;
}

Status CheckViewerOutput(const std::string& path, bool overwrite) {
  if (path.empty()) return Status::Error("--output FILE.html is required");
  const fs::path file(path);
  const std::string extension = Lowercase(file.extension().string());
  if (extension != ".html" && extension != ".htm") {
    return Status::Error("--output must name a .html file, got '" + path + "'");
  }
  std::error_code ec;
  if (fs::is_directory(file, ec)) {
    return Status::Error("--output '" + path + "' is a directory");
  }
  if (fs::exists(file, ec) && !overwrite) {
    return Status::Error("--output '" + path +
                         "' exists (use --overwrite to replace it)");
  }
  const fs::path parent =
      file.has_parent_path() ? file.parent_path() : fs::path(".");
  if (!fs::is_directory(parent, ec)) {
    return Status::Error("--output '" + path + "': the directory '" +
                         parent.string() + "' does not exist");
  }
  return Status::OK();
}

Status WriteViewerPage(const std::string& path, const std::string& html) {
  const fs::path file(path);
  const fs::path parent =
      file.has_parent_path() ? file.parent_path() : fs::path(".");
  const fs::path temporary = parent / ("." + file.filename().string() +
                                       ".tmp-" + std::to_string(::getpid()));
  const std::string error_prefix = "--output '" + path + "': cannot write ";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) {
      return Status::Error(error_prefix + "in '" + parent.string() + "' (" +
                           std::strerror(errno) + ")");
    }
    out.write(html.data(), static_cast<std::streamsize>(html.size()));
    out.close();
    if (!out) {
      const std::string reason = std::strerror(errno);
      std::error_code ec;
      fs::remove(temporary, ec);
      return Status::Error(error_prefix + "the page (" + reason + ")");
    }
  }
  std::error_code ec;
  fs::rename(temporary, file, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    return Status::Error(error_prefix + "the page (" + ec.message() + ")");
  }
  return Status::OK();
}

}  // namespace tools
}  // namespace nrsfm
