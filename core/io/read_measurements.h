// Measurements from an input file (docs/guide.md, "Input formats"): a MATLAB
// .mat file, a text matrix W, an observation list, or detector keypoints.
//
// Format (options.format = kAuto decides by the extension, any case, or
// a folder):
//   .mat                      MATLAB v4, v5 or v7.3 (core/io/mat_io.h)
//   .txt .csv .tsv .dat       text matrix W, 2FM × P (core/io/text_io.h)
//   .obs .list                observation list "frame camera point u v"
//   .json                     COCO keypoint results (core/io/keypoint_io.h)
//   a folder                  OpenPose's per-frame .json files (same), or
//                             the tracks.mat in it (kTrackOutputFile) when
//                             it holds one: the output of `nrsfm track`
// Keypoint inputs are monocular and in pixels with v down, and carry each
// keypoint's score (InputDetails::confidence); options.keypoints says how
// they are read.
//
// In a .mat file the measurements come from the variable options.variable,
// or, when it is "", from the first that exists of
//   W      2FM × P, rows u, v per (frame, camera) (core/model/measurements.h);
//   P3_gt  3F × P, block layout [x rows; y rows; z rows] (monocular): the
//          2-D input is W_t = (x_t, y_t);
//   X      3 × P × F (a 3 × P matrix is one frame), W_t = rows 0, 1 of X_t.
// A variable named with options.variable is read as P3_gt when so named, as
// X when named X or 3-D, as W otherwise.
// The number of cameras M of a W variable is the file's variable `cameras`
// when it has one (nrsfm synth writes it): a positive integer scalar that
// divides W's rows into 2 per frame and camera; otherwise
// options.num_cameras, 1 when that is 0. A num_cameras other than 0 that
// disagrees with the file's `cameras` is an error naming both counts.
// NaN marks a missing entry (both coordinates of a point or neither).
// options.mask_variable optionally names a (2FM) × P (rows u, v, which must
// agree) or (FM) × P variable of the same file: nonzero = visible. An entry
// is visible when the mask says so AND W holds numbers there; W is set to
// NaN where it is not visible.
#ifndef NRSFM_CORE_IO_READ_MEASUREMENTS_H_
#define NRSFM_CORE_IO_READ_MEASUREMENTS_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/io/keypoint_io.h"
#include "core/model/measurements.h"
#include "core/model/status.h"

namespace nrsfm {

// The file of `nrsfm track`'s output folder that reconstruct reads when
// given the folder.
inline constexpr char kTrackOutputFile[] = "tracks.mat";

enum class InputFormat {
  kAuto,      // by the extension (above)
  kMat,       // MATLAB .mat
  kText,      // text matrix W
  kList,      // observation list
  kCoco,      // COCO keypoint results (.json)
  kOpenPose,  // a folder of OpenPose per-frame .json files
};
// "auto", "mat", "text", "list", "coco", "openpose"; the error lists them.
const char* InputFormatName(InputFormat format);
Status ParseInputFormat(const std::string& name, InputFormat* format);

struct InputOptions {
  // .mat variable with the measurements; "" = auto: W, then P3_gt, then X.
  std::string variable;
  // .mat variable with the visibility mask, nonzero = visible; "" = none.
  std::string mask_variable;
  // M, the number of synchronised cameras of a W with 2FM rows; 0 = from
  // the input: a .mat file's `cameras` variable, an observation list's
  // largest camera index + 1, else 1. A value >= 1 must agree with what the
  // file records (an error names both). P3_gt and X are monocular (M = 1).
  // Keypoint inputs (M = 1).
  int num_cameras = 0;
  InputFormat format = InputFormat::kAuto;
  // How keypoint inputs are read: frame order, OpenPose part, the least
  // score of a visible keypoint.
  KeypointOptions keypoints;
  // Pinhole intrinsics, column c = (fx, fy, cx, cy) of camera c in pixels
  // (one column: every camera); they replace a .mat file's Kcam. Empty
  // (4 × 0): Kcam when the file has it (a 3 × 3 [fx s cx; 0 fy cy; 0 0 1]
  // or 3 × 3 × M; skew s must be 0), else none.
  Eigen::Matrix4Xd intrinsics = Eigen::Matrix4Xd(4, 0);

  // Errors on num_cameras < 0, a format not in the enum and invalid
  // keypoint options.
  Status Check() const;
};

// What an input holds besides the measurements.
struct InputDetails {
  // (F·M) × P: the detector's score of each keypoint of a keypoint input
  // (Keypoints::confidence: NaN in frames with no person); empty for the
  // other formats, which hold no scores.
  Eigen::ArrayXXd confidence;
  // Lines for the user about the input (keypoint inputs: frames with no
  // person, frames with several); often empty.
  std::vector<std::string> warnings;
};

// Parses "fx,fy,cx,cy" (one camera) or several such groups joined by ';'
// (camera 0 first) into a 4 × M matrix; fx, fy > 0. Errors quote the text.
Status ParseIntrinsics(const std::string& text, Eigen::Matrix4Xd* intrinsics);

// Reads `path` (header) into `measurements` and, when `details` is not
// null, `details`. Errors name the file and what is wrong with it.
Status ReadMeasurements(const std::string& path, const InputOptions& options,
                        Measurements* measurements,
                        InputDetails* details = nullptr);

// Sets `*w` (2FM × P, M = num_cameras) to NaN where `mask` says an entry is
// not visible (0 = not visible, any other number = visible). `mask` is
// 2FM × P (rows u and v of a view must agree) or FM × P. Errors name `name`
// (e.g. "drink.mat: mask M") on another size, NaN or Inf, and rows u and v
// that differ. The mask variable of ReadMeasurements goes through this.
Status ApplyVisibilityMask(const Eigen::MatrixXd& mask, const std::string& name,
                           int num_cameras, Eigen::MatrixXd* w);

}  // namespace nrsfm

#endif  // NRSFM_CORE_IO_READ_MEASUREMENTS_H_
