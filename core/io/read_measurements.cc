#include "core/io/read_measurements.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <vector>

#include "core/io/mat_io.h"
#include "core/io/text_io.h"
#include "core/model/enum_names.h"
#include "core/model/option_checker.h"
#include "core/model/shape_layouts.h"

namespace nrsfm {
namespace {

constexpr EnumName<InputFormat> kInputFormatNames[] = {
    {InputFormat::kAuto, "auto"}, {InputFormat::kMat, "mat"},
    {InputFormat::kText, "text"}, {InputFormat::kList, "list"},
    {InputFormat::kCoco, "coco"}, {InputFormat::kOpenPose, "openpose"},
};

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) {
    return static_cast<char>(std::tolower(c));
  });
  return s;
}

// `path`, or the tracks file in it when it is a folder written by `nrsfm
// track`.
std::string TrackOutputOr(const std::string& path) {
  std::error_code ec;
  const std::filesystem::path tracks =
      std::filesystem::path(path) / kTrackOutputFile;
  if (std::filesystem::is_directory(path, ec) &&
      std::filesystem::is_regular_file(tracks, ec)) {
    return tracks.string();
  }
  return path;
}

Status DetectFormat(const std::string& path, InputFormat requested,
                    InputFormat* format) {
  if (requested != InputFormat::kAuto) {
    *format = requested;
    return Status::OK();
  }
  const std::string ext =
      Lower(std::filesystem::path(path).extension().string());
  std::error_code ec;
  if (ext != ".mat" && std::filesystem::is_directory(path, ec)) {
    *format = InputFormat::kOpenPose;
  } else if (ext == ".mat") {
    *format = InputFormat::kMat;
  } else if (ext == ".txt" || ext == ".csv" || ext == ".tsv" || ext == ".dat") {
    *format = InputFormat::kText;
  } else if (ext == ".obs" || ext == ".list") {
    *format = InputFormat::kList;
  } else if (ext == ".json") {
    *format = InputFormat::kCoco;
  } else {
    return Status::Error(
        path + ": cannot tell the input format from the extension '" + ext +
        "' (.mat; .txt/.csv/.tsv/.dat; .obs/.list; .json; a folder of OpenPose "
        ".json files); set the format");
  }
  return Status::OK();
}

// Picks the measurement variable: the requested one, else W, P3_gt, X.
Status ChooseVariable(const std::string& path, const std::string& requested,
                      std::string* variable) {
  if (!requested.empty()) {
    *variable = requested;
    return Status::OK();
  }
  std::vector<std::string> names;
  NRSFM_RETURN_IF_ERROR(ListMatVariables(path, &names));
  for (const char* candidate : {"W", "P3_gt", "X"}) {
    if (std::find(names.begin(), names.end(), candidate) != names.end()) {
      *variable = candidate;
      return Status::OK();
    }
  }
  std::string joined;
  for (const std::string& name : names)
    joined += (joined.empty() ? "" : ", ") + name;
  return Status::Error(
      path + ": none of the variables W, P3_gt, X is in the file (it has: " +
      (joined.empty() ? "(none)" : joined) + "); name one");
}

// Reads the chosen variable as a (2FM) × P matrix W; *monocular says it
// was read from a 3-D variable (P3_gt, X), M = 1.
Status ReadWFromMat(const std::string& path, const std::string& variable,
                    int num_cameras, Eigen::MatrixXd* w, bool* monocular) {
  *monocular = true;
  const std::string name = path + ": " + variable;
  if (variable == "P3_gt") {
    Eigen::MatrixXd block;
    NRSFM_RETURN_IF_ERROR(ReadMatVariable(path, variable, &block));
    std::vector<Eigen::Matrix3Xd> frames;
    NRSFM_RETURN_IF_ERROR(FramesFromBlockLayout(block, name, &frames));
    if (num_cameras > 1) {
      return Status::Error(name +
                           " holds monocular data; num_cameras must be 1");
    }
    *w = OrthographicW(frames);
    return Status::OK();
  }
  std::vector<Eigen::MatrixXd> slices;
  std::vector<std::size_t> dims;
  NRSFM_RETURN_IF_ERROR(ReadMatArray3(path, variable, &slices, &dims));
  // An empty array (e.g. 4 x 3 x 0) has no slice at all.
  if (slices.empty()) {
    return Status::Error(name + " is empty (" + MatDimsString(dims) + ")");
  }
  if (variable == "X" || slices.size() > 1) {
    std::vector<Eigen::Matrix3Xd> frames;
    NRSFM_RETURN_IF_ERROR(FramesFromArray3(slices, name, &frames));
    if (num_cameras > 1) {
      return Status::Error(name +
                           " holds monocular data; num_cameras must be 1");
    }
    *w = OrthographicW(frames);
    return Status::OK();
  }
  *w = std::move(slices[0]);
  *monocular = false;
  return Status::OK();
}

// The number of cameras of a W read from a .mat file (see the header).
Status CamerasOfMatFile(const std::string& path, const Eigen::MatrixXd& w,
                        int requested, int* num_cameras) {
  std::vector<std::string> names;
  NRSFM_RETURN_IF_ERROR(ListMatVariables(path, &names));
  *num_cameras = requested == 0 ? 1 : requested;
  if (std::find(names.begin(), names.end(), "cameras") == names.end()) {
    return Status::OK();
  }
  const std::string name = path + ": variable 'cameras'";
  Eigen::MatrixXd value;
  NRSFM_RETURN_IF_ERROR(ReadMatVariable(path, "cameras", &value));
  if (value.rows() != 1 || value.cols() != 1) {
    return Status::Error(name +
                         " must be a scalar (the number of cameras M), got a " +
                         std::to_string(value.rows()) + " x " +
                         std::to_string(value.cols()) + " matrix");
  }
  const double cameras = value(0, 0);
  if (!(std::isfinite(cameras) && cameras >= 1.0 && cameras <= 1e6 &&
        cameras == std::floor(cameras))) {
    std::ostringstream got;
    got << cameras;
    return Status::Error(
        name + " must be a positive integer (the number of cameras M), got " +
        got.str());
  }
  const int file_cameras = static_cast<int>(cameras);
  if (w.rows() > 0 && w.rows() % (2 * file_cameras) != 0) {
    return Status::Error(name + " = " + std::to_string(file_cameras) +
                         " does not divide the " + std::to_string(w.rows()) +
                         " rows of W into 2 rows per frame and camera");
  }
  if (requested != 0 && requested != file_cameras) {
    return Status::Error(
        path + ": the file records cameras = " + std::to_string(file_cameras) +
        " (variable 'cameras') but " + std::to_string(requested) +
        " camera(s) were asked for");
  }
  *num_cameras = file_cameras;
  return Status::OK();
}

}  // namespace

Status ApplyVisibilityMask(const Eigen::MatrixXd& mask, const std::string& name,
                           int num_cameras, Eigen::MatrixXd* w) {
  const Eigen::Index views = w->rows() / 2;
  if (mask.cols() != w->cols() ||
      (mask.rows() != w->rows() && mask.rows() != views)) {
    return Status::Error(
        name + " is " + std::to_string(mask.rows()) + " x " +
        std::to_string(mask.cols()) + "; expected " +
        std::to_string(w->rows()) + " x " + std::to_string(w->cols()) + " or " +
        std::to_string(views) + " x " + std::to_string(w->cols()) + " (W is " +
        std::to_string(w->rows()) + " x " + std::to_string(w->cols()) +
        ", M = " + std::to_string(num_cameras) + ")");
  }
  if (!mask.allFinite())
    return Status::Error(name + " holds NaN or Inf; expected 0/1");
  const bool per_row = mask.rows() == w->rows();
  for (Eigen::Index view = 0; view < views; ++view) {
    for (Eigen::Index p = 0; p < w->cols(); ++p) {
      bool visible = mask(per_row ? 2 * view : view, p) != 0.0;
      if (per_row && visible != (mask(2 * view + 1, p) != 0.0)) {
        return Status::Error(name + ": rows " + std::to_string(2 * view + 1) +
                             " and " + std::to_string(2 * view + 2) +
                             " (u and v of one view) differ at column " +
                             std::to_string(p + 1) + " (1-based)");
      }
      if (!visible) {
        (*w)(2 * view, p) = std::nan("");
        (*w)(2 * view + 1, p) = std::nan("");
      }
    }
  }
  return Status::OK();
}

namespace {

// The Kcam variable of `path`: 3 × 3 or 3 × 3 × M upper-triangular pinhole
// matrices, one for every camera or one per camera.
Status ReadKcam(const std::string& path, int num_cameras,
                Eigen::Matrix4Xd* intrinsics) {
  const std::string name = path + ": Kcam";
  std::vector<Eigen::MatrixXd> slices;
  std::vector<std::size_t> dims;
  NRSFM_RETURN_IF_ERROR(ReadMatArray3(path, "Kcam", &slices, &dims));
  if (dims.size() < 2 || dims[0] != 3 || dims[1] != 3 ||
      (slices.size() != 1 &&
       slices.size() != static_cast<std::size_t>(num_cameras))) {
    return Status::Error(name + " is " + MatDimsString(dims) +
                         "; expected 3 x 3 or 3 x 3 x " +
                         std::to_string(num_cameras) + " (one per camera)");
  }
  intrinsics->resize(4, num_cameras);
  for (int c = 0; c < num_cameras; ++c) {
    const Eigen::MatrixXd& k = slices[slices.size() == 1 ? 0 : c];
    const std::string which =
        slices.size() == 1 ? name
                           : name + "(:, :, " + std::to_string(c + 1) + ")";
    if (!k.allFinite() || k(1, 0) != 0.0 || k(2, 0) != 0.0 || k(2, 1) != 0.0 ||
        !(k(2, 2) > 0.0)) {
      return Status::Error(
          which + " is not a pinhole matrix [fx s cx; 0 fy cy; 0 0 1]");
    }
    const Eigen::Matrix3d normalized = k / k(2, 2);
    if (std::abs(normalized(0, 1)) > 1e-9 * std::abs(normalized(0, 0))) {
      return Status::Error(which + " has a skew of " +
                           std::to_string(normalized(0, 1)) +
                           "; only zero skew is supported");
    }
    if (!(normalized(0, 0) > 0.0) || !(normalized(1, 1) > 0.0)) {
      return Status::Error(which +
                           ": the focal lengths fx, fy must be positive");
    }
    intrinsics->col(c) << normalized(0, 0), normalized(1, 1), normalized(0, 2),
        normalized(1, 2);
  }
  return Status::OK();
}

Status ReadMatMeasurements(const std::string& path, const InputOptions& options,
                           Measurements* measurements) {
  std::string variable;
  NRSFM_RETURN_IF_ERROR(ChooseVariable(path, options.variable, &variable));
  Eigen::MatrixXd w;
  bool monocular = true;
  NRSFM_RETURN_IF_ERROR(
      ReadWFromMat(path, variable, options.num_cameras, &w, &monocular));
  int num_cameras = 1;
  if (!monocular) {
    NRSFM_RETURN_IF_ERROR(
        CamerasOfMatFile(path, w, options.num_cameras, &num_cameras));
  }
  const std::string name = path + ": " + variable;
  // A W of the wrong shape is reported by FromMatrixWithNaN, not by the mask.
  if (!options.mask_variable.empty() && w.size() > 0 &&
      w.rows() % (2 * num_cameras) == 0) {
    Eigen::MatrixXd mask;
    NRSFM_RETURN_IF_ERROR(ReadMatVariable(path, options.mask_variable, &mask));
    NRSFM_RETURN_IF_ERROR(ApplyVisibilityMask(
        mask, path + ": mask " + options.mask_variable, num_cameras, &w));
  }
  NRSFM_RETURN_IF_ERROR(
      Measurements::FromMatrixWithNaN(w, num_cameras, name, measurements));
  std::vector<std::string> names;
  NRSFM_RETURN_IF_ERROR(ListMatVariables(path, &names));
  if (std::find(names.begin(), names.end(), "Kcam") != names.end()) {
    NRSFM_RETURN_IF_ERROR(
        ReadKcam(path, num_cameras, &measurements->intrinsics));
  }
  return Status::OK();
}

}  // namespace

const char* InputFormatName(InputFormat format) {
  return NameOf(kInputFormatNames, format);
}

Status ParseInputFormat(const std::string& name, InputFormat* format) {
  return ParseName(kInputFormatNames, name, "input format", format);
}

Status InputOptions::Check() const {
  OptionChecker check("input options");
  check.Require(num_cameras >= 0,
                "num_cameras must be >= 1 (or 0: from the file), got " +
                    std::to_string(num_cameras));
  check.Require(NameOf(kInputFormatNames, format) != std::string("unknown"),
                "invalid format " + std::to_string(static_cast<int>(format)));
  check.Nested(keypoints.Check());
  return check.status();
}

Status ParseIntrinsics(const std::string& text, Eigen::Matrix4Xd* intrinsics) {
  std::vector<double> values;
  std::string item;
  int groups = 1;
  bool bad = false;
  for (std::size_t i = 0; i <= text.size(); ++i) {
    const char ch = i < text.size() ? text[i] : ',';
    if (ch != ',' && ch != ';') {
      item += ch;
      continue;
    }
    char* end = nullptr;
    const double value = std::strtod(item.c_str(), &end);
    bad |= item.empty() || *end != '\0' || !std::isfinite(value);
    values.push_back(value);
    item.clear();
    if (ch == ';') {
      ++groups;
      bad |= values.size() != static_cast<std::size_t>(4 * (groups - 1));
    }
  }
  if (bad || values.size() != static_cast<std::size_t>(4 * groups)) {
    return Status::Error("intrinsics \"" + text +
                         "\": expected fx,fy,cx,cy (pixels), one group per "
                         "camera joined by ';'");
  }
  Eigen::Matrix4Xd parsed(4, groups);
  for (int c = 0; c < groups; ++c) {
    for (int i = 0; i < 4; ++i) parsed(i, c) = values[4 * c + i];
    if (!(parsed(0, c) > 0.0) || !(parsed(1, c) > 0.0)) {
      return Status::Error("intrinsics \"" + text +
                           "\": the focal lengths fx, fy must be positive");
    }
  }
  *intrinsics = parsed;
  return Status::OK();
}

Status ReadMeasurements(const std::string& given_path,
                        const InputOptions& options, Measurements* measurements,
                        InputDetails* details) {
  NRSFM_RETURN_IF_ERROR(options.Check());
  const std::string path = TrackOutputOr(given_path);
  InputFormat format = InputFormat::kAuto;
  NRSFM_RETURN_IF_ERROR(DetectFormat(path, options.format, &format));
  if (format != InputFormat::kMat &&
      (!options.variable.empty() || !options.mask_variable.empty())) {
    return Status::Error(
        path +
        ": a variable or mask variable can only be named for .mat "
        "input (this is read as " +
        InputFormatName(format) + ")");
  }
  Measurements m;
  InputDetails found;
  if (format == InputFormat::kCoco || format == InputFormat::kOpenPose) {
    if (options.num_cameras > 1) {
      return Status::Error(path + ": keypoint files hold one camera, but " +
                           std::to_string(options.num_cameras) +
                           " cameras were asked for");
    }
    Keypoints keypoints;
    NRSFM_RETURN_IF_ERROR(
        format == InputFormat::kCoco
            ? ReadCocoKeypoints(path, options.keypoints, &keypoints)
            : ReadOpenPoseFolder(path, options.keypoints, &keypoints));
    m = std::move(keypoints.measurements);
    found.confidence = std::move(keypoints.confidence);
    found.warnings = std::move(keypoints.warnings);
  } else if (format == InputFormat::kMat) {
    NRSFM_RETURN_IF_ERROR(ReadMatMeasurements(path, options, &m));
  } else if (format == InputFormat::kText) {
    Eigen::MatrixXd w;
    NRSFM_RETURN_IF_ERROR(ReadTextMatrix(path, &w));
    NRSFM_RETURN_IF_ERROR(Measurements::FromMatrixWithNaN(
        w, std::max(options.num_cameras, 1), path, &m));
  } else {
    NRSFM_RETURN_IF_ERROR(ReadObservationList(path, &m));
    if (options.num_cameras != 0 && options.num_cameras != m.num_cameras) {
      return Status::Error(path + ": the list has " +
                           std::to_string(m.num_cameras) +
                           " camera(s) but num_cameras is " +
                           std::to_string(options.num_cameras));
    }
  }
  if (options.intrinsics.cols() != 0) {
    if (options.intrinsics.cols() != 1 &&
        options.intrinsics.cols() != m.num_cameras) {
      return Status::Error(path + ": intrinsics were given for " +
                           std::to_string(options.intrinsics.cols()) +
                           " cameras, but the input has " +
                           std::to_string(m.num_cameras));
    }
    m.intrinsics.resize(4, m.num_cameras);
    for (int c = 0; c < m.num_cameras; ++c) {
      m.intrinsics.col(c) =
          options.intrinsics.col(options.intrinsics.cols() == 1 ? 0 : c);
    }
  }
  NRSFM_RETURN_IF_ERROR(m.Validate().WithContext(path));
  *measurements = std::move(m);
  if (details != nullptr) *details = std::move(found);
  return Status::OK();
}

}  // namespace nrsfm
