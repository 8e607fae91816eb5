// nrsfm_track: the point tracker of `nrsfm track` (track/tracker.h;
// docs/tracking.md) as a MEX function for Octave (mkoctfile --mex) and
// MATLAB (mex); docs/matlab.md.
//
//   [tracks, info] = nrsfm_track(frames, 'Name', value, ...)
//
// frames  a folder of images or a video file (char), or an H x W x F
//         (grey) or H x W x 3 x F (RGB) uint8 array.
// Names   (case-insensitive)
//           'queries'  N x 4 [point, frame, x, y]: point ids (distinct
//                      integers >= 0), the frame number each point starts at
//                      (an array's or a video's frames are numbered 0 ... F-1,
//                      a folder's by the numbers in the file names), and its
//                      position in pixels, x right, y down, (0, 0) the centre
//                      of the top-left pixel (MATLAB's (column - 1, row - 1));
//                      without it the tracker chooses points in the first
//                      frame;
//           'mask'     the object's region: frames of the same kind and size,
//                      nonzero = object;
//         and every option of `nrsfm track` (track_method, patch_size,
//         pyramid_levels, window_frames, rank, ...: the error for an unknown
//         name lists them), a char value for a text option, a numeric or
//         logical scalar otherwise.
// tracks  a struct: W (2F x P, rows x, y of each frame, NaN where the point is
//         judged occluded or has not started: what nrsfm_reconstruct takes),
//         visible (F x P logical), positions (F x P x 2, x and y of every frame
//         from each point's query on, the basis' prediction where occluded;
//         NaN before), frame_numbers (F x 1), point_ids (1 x P); pixels in the
//         convention of 'queries'.
// info    result.json of `nrsfm track` as a struct (jsondecode): the ranks
//         used per window, points lost, the visible fraction, seconds.
//
// Bad input is an error (identifier nrsfm:error) with the tracker's message;
// no C++ object is alive when it is raised (MATLAB's mexErrMsgIdAndTxt does
// not unwind C++ frames).
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "matlab/mex_util.h"
#include "mex.h"
#include "tools/command_flags.h"
#include "tools/flag_table.h"
#include "tools/track_summary.h"
#include "track/frame_source.h"
#include "track/tracker.h"

namespace {

namespace mex = ::nrsfm::mex;
namespace track = ::nrsfm::track;
using nrsfm::Status;

struct Outcome {
  std::string error;  // "" = success
  mxArray* tracks = nullptr;
  mxArray* summary_json = nullptr;  // a char array, decoded by jsondecode
};

// Frames from a char path (a folder or a video) or a uint8 array: H x W x F
// grey or H x W x 3 x F RGB (MATLAB's column-major order; OpenCV's images are
// row-major, colour BGR).
Status FramesOf(const mxArray* a, const std::string& what,
                track::FrameSource* source) {
  if (mxIsChar(a)) {
    std::string path;
    NRSFM_RETURN_IF_ERROR(mex::ValueText(a, what, &path));
    std::error_code ec;
    return (std::filesystem::is_directory(path, ec)
                ? track::FrameSource::OpenFolder(path, source)
                : track::FrameSource::OpenVideo(path, source))
        .WithContext(what);
  }
  const mwSize n = mxGetNumberOfDimensions(a);
  const mwSize* dims = mxGetDimensions(a);
  const bool colour = n == 4 && dims[2] == 3;
  if (!mxIsUint8(a) || mxIsComplex(a) || !(n == 2 || n == 3 || colour)) {
    return Status::Error(
        what +
        " must be a folder, a video file, or an H x W x F or H x W x 3 x F "
        "uint8 array; got a " +
        std::string(mxGetClassName(a)) + " array of size " + mex::SizeText(a));
  }
  const int height = static_cast<int>(dims[0]);
  const int width = static_cast<int>(dims[1]);
  const int frames = colour ? static_cast<int>(dims[3])
                            : (n == 3 ? static_cast<int>(dims[2]) : 1);
  const std::uint8_t* data = static_cast<const std::uint8_t*>(mxGetData(a));
  const std::size_t plane = static_cast<std::size_t>(height) * width;
  std::vector<cv::Mat> images;
  for (int f = 0; f < frames; ++f) {
    cv::Mat image(height, width, colour ? CV_8UC3 : CV_8UC1);
    for (int y = 0; y < height; ++y) {
      std::uint8_t* row = image.ptr<std::uint8_t>(y);
      for (int x = 0; x < width; ++x) {
        const std::size_t at = y + static_cast<std::size_t>(height) * x;
        if (colour) {
          const std::uint8_t* first = data + 3 * plane * f + at;
          row[3 * x] = first[2 * plane];  // B
          row[3 * x + 1] = first[plane];  // G
          row[3 * x + 2] = first[0];      // R
        } else {
          row[x] = data[plane * f + at];
        }
      }
    }
    images.push_back(std::move(image));
  }
  return track::FrameSource::FromImages(std::move(images), source)
      .WithContext(what);
}

Status QueriesOf(const mxArray* a, std::vector<track::Query>* queries) {
  Eigen::MatrixXd table;
  NRSFM_RETURN_IF_ERROR(mex::ToMatrix(a, "queries", &table));
  if (table.cols() != 4 || table.rows() == 0) {
    return Status::Error("queries must be N x 4 [point, frame, x, y], got " +
                         mex::SizeText(a));
  }
  for (Eigen::Index r = 0; r < table.rows(); ++r) {
    const double point = table(r, 0), frame = table(r, 1);
    if (point != std::floor(point) || frame != std::floor(frame) || point < 0 ||
        std::abs(frame) > 1e9 || point > 1e9 || !std::isfinite(table(r, 2)) ||
        !std::isfinite(table(r, 3))) {
      return Status::Error("queries row " + std::to_string(r + 1) +
                           ": point and frame must be integers, point >= 0, "
                           "x and y finite");
    }
    queries->push_back({static_cast<int>(point), static_cast<int>(frame),
                        table(r, 2), table(r, 3)});
  }
  return Status::OK();
}

mxArray* TracksStruct(const track::Tracks& result) {
  const mwSize f = result.x.rows(), p = result.x.cols();
  mxArray* w = mex::NewArray({2 * f, p});
  mxArray* visible = mxCreateLogicalMatrix(f, p);
  mxArray* positions = mex::NewArray({f, p, 2});
  double* wd = mxGetPr(w);
  mxLogical* vd = mxGetLogicals(visible);
  double* pd = mxGetPr(positions);
  for (mwSize t = 0; t < f; ++t) {
    for (mwSize q = 0; q < p; ++q) {
      const bool seen = result.visible(t, q) != 0;
      vd[t + f * q] = seen;
      wd[2 * t + 2 * f * q] = seen ? result.x(t, q) : NAN;
      wd[2 * t + 1 + 2 * f * q] = seen ? result.y(t, q) : NAN;
      pd[t + f * q] = result.x(t, q);
      pd[t + f * q + f * p] = result.y(t, q);
    }
  }
  mxArray* frame_numbers = mex::NewArray({f, 1});
  for (mwSize t = 0; t < f; ++t)
    mxGetPr(frame_numbers)[t] = result.frame_numbers[t];
  mxArray* point_ids = mex::NewArray({1, p});
  for (mwSize q = 0; q < p; ++q) mxGetPr(point_ids)[q] = result.point_ids[q];
  const char* fields[] = {"W", "visible", "positions", "frame_numbers",
                          "point_ids"};
  mxArray* s = mxCreateStructMatrix(1, 1, 5, fields);
  mxSetField(s, 0, "W", w);
  mxSetField(s, 0, "visible", visible);
  mxSetField(s, 0, "positions", positions);
  mxSetField(s, 0, "frame_numbers", frame_numbers);
  mxSetField(s, 0, "point_ids", point_ids);
  return s;
}

Status Run(int nlhs, int nrhs, const mxArray* prhs[], Outcome* outcome) {
  if (nrhs < 1 || nrhs % 2 != 1) {
    return Status::Error(
        "usage: [tracks, info] = nrsfm_track(frames, 'Name', value, ...)");
  }
  if (nlhs > 2) return Status::Error("nrsfm_track returns at most two outputs");
  nrsfm::tools::CommandFlags flags;
  const mxArray* mask_array = nullptr;
  std::vector<track::Query> queries;
  const std::vector<std::pair<std::string, std::string>> names =
      mex::OptionNames({nrsfm::tools::FlagRole::kTracking});
  for (int i = 1; i < nrhs; i += 2) {
    if (!mxIsChar(prhs[i])) {
      return Status::Error("argument " + std::to_string(i + 1) +
                           " must be an option name (a char row)");
    }
    std::string name;
    NRSFM_RETURN_IF_ERROR(mex::ValueText(prhs[i], "an option name", &name));
    const std::string lower = mex::Lower(name);
    if (lower == "queries") {
      NRSFM_RETURN_IF_ERROR(QueriesOf(prhs[i + 1], &queries));
      continue;
    }
    if (lower == "mask") {
      mask_array = prhs[i + 1];
      continue;
    }
    NRSFM_RETURN_IF_ERROR(
        mex::SetOption(names, name, prhs[i + 1], "queries, mask", &flags));
  }
  nrsfm::tools::FlagTargets targets;
  NRSFM_RETURN_IF_ERROR(nrsfm::tools::ApplyFlags(flags, &targets));
  track::FrameSource frames, mask;
  NRSFM_RETURN_IF_ERROR(FramesOf(prhs[0], "frames", &frames));
  if (mask_array != nullptr) {
    NRSFM_RETURN_IF_ERROR(FramesOf(mask_array, "mask", &mask));
  }
  track::Tracks result;
  NRSFM_RETURN_IF_ERROR(
      track::TrackPoints(&frames, mask_array != nullptr ? &mask : nullptr,
                         queries, targets.track, nullptr, &result));
  outcome->tracks = TracksStruct(result);
  const nlohmann::json summary = nrsfm::tools::TrackSummaryJson(
      flags, frames.name(), frames.size().width, frames.size().height, result);
  outcome->summary_json = mxCreateString(summary.dump().c_str());
  return Status::OK();
}

}  // namespace

void mexFunction(int nlhs, mxArray* plhs[], int nrhs, const mxArray* prhs[]) {
  // Kept across calls, so that no C++ object of this call is alive when
  // mexErrMsgIdAndTxt leaves it.
  static Outcome outcome;
  outcome = Outcome();
  outcome.error = mex::ErrorOf([&] { return Run(nlhs, nrhs, prhs, &outcome); });
  if (!outcome.error.empty()) {
    if (outcome.tracks != nullptr) mxDestroyArray(outcome.tracks);
    if (outcome.summary_json != nullptr) mxDestroyArray(outcome.summary_json);
    mexErrMsgIdAndTxt("nrsfm:error", "%s", outcome.error.c_str());
  }
  plhs[0] = outcome.tracks;
  if (nlhs > 1) {
    mexCallMATLAB(1, &plhs[1], 1, &outcome.summary_json, "jsondecode");
  }
  mxDestroyArray(outcome.summary_json);
}
