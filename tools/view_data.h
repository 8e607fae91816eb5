// What `nrsfm view` shows, gathered from a result directory and, optionally,
// the ground truth and the 2D tracks: the per-frame 3D shapes, the truth after
// the e3D alignment, per-frame errors, the edges to draw and the 2D tracks
// with their reprojections. No HTML here (see tools/view_page.h).
//
// Frames, units: everything is in the units of the measurements W. With a
// truth the 3D shapes are in the frame that `nrsfm evaluate` scores in
// (core/eval/metrics.h EvaluateShapes: the object frame, points_object.csv, for
// S + Rs truth; camera 0's frame, points_camera.csv, otherwise), without one
// in camera 0's frame (x, y along the image's u, v, z the depth); the frame
// is named in ViewData::scoring_frame,
// each frame centred on the mean of its P points, as the metrics centre them
// (core/eval/metrics.h). The truth is mapped into the estimate's frame by Yᵀ, Y
// the one global e3D alignment (estimate → truth), so distances between the two
// are the ones e3D averages.
#ifndef NRSFM_TOOLS_VIEW_DATA_H_
#define NRSFM_TOOLS_VIEW_DATA_H_

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "core/eval/metrics.h"
#include "core/io/read_measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"

namespace nrsfm {
namespace tools {

struct ViewDataOptions {
  std::string
      result_dir;  // required: a directory written by `nrsfm reconstruct`
  // Ground truth: a .mat (S + Rs, P3_gt or X; core/io/ground_truth.h) or a
  // result directory; "" = none. `truth_variable` as --truth_var.
  std::string truth_path, truth_variable;
  // The 2D tracks the result was reconstructed from (any input format of
  // core/io/read_measurements.h, read with `input`); "" = none. Read with the
  // result's M cameras (input.num_cameras is not used).
  std::string input_path;
  InputOptions input;
  // A folder of the frames (one image per frame of the result, numbered as
  // `nrsfm track` reads them: track/tracks.h, ListFrameFiles), drawn under
  // the 2D view; "" = none. PNG, JPEG, BMP or WebP (what a browser shows),
  // one camera.
  std::string frames_dir;
};

struct ViewData {
  int num_frames = 0;         // F
  int num_cameras = 0;        // M
  int num_points = 0;         // P
  int num_bases = -1;         // K from result.json; -1 when unknown
  std::string scoring_frame;  // the frame of `estimate`, in words
  // result.json's camera (core/io/result_reader.h ReadResultCamera): with a
  // perspective one points_camera.csv holds the translation, and the
  // reprojection is the pinhole projection with result.json's intrinsics.
  CameraModel camera_model = CameraModel::kWeakPerspective;

  // F entries, 3 × P: the estimate in the scoring frame, centred per frame.
  std::vector<Eigen::Matrix3Xd> estimate;

  // With truth only (has_truth): the truth, centred per frame, mapped into the
  // estimate's frame by Yᵀ; `frame_error`(t) = (1/P) Σ_p ||X_tp − Y X̂_tp|| / s,
  // the term of frame t in e3D (its mean over t is metrics.e3d); `metrics`
  // as `nrsfm evaluate` prints them. A perspective result is aligned with one
  // global scale c as well (truth shown as Yᵀ X / c; the mean of frame_error
  // is metrics.e3d_scaled).
  bool has_truth = false;
  std::vector<Eigen::Matrix3Xd> truth_aligned;
  Eigen::VectorXd frame_error;
  ShapeErrors metrics;

  // Point pairs (i < j, 0-based) to draw, and where they came from.
  std::vector<std::array<int, 2>> edges;
  std::string edge_source;

  // (2FM) × P in the layout of Measurements::W: the reprojection
  // w_tcp = Π X_tc[:, p] + T_tc of every point (points_camera.csv and
  // translations.csv), missing ones too.
  Eigen::MatrixXd reprojection;
  // With tracks only (has_tracks): the input tracks, (2FM) × P, NaN where a
  // point is not visible; `frame_reprojection_rms`(t) the RMS 2D distance
  // between tracks and reprojections over the visible entries of frame t (all
  // cameras; NaN when none is visible) and `reprojection_rms` over all;
  // points and frames the reconstruction left out (NaN) are not counted.
  bool has_tracks = false;
  Eigen::MatrixXd tracks;
  Eigen::VectorXd frame_reprojection_rms;
  double reprojection_rms = 0.0;

  // With points_covariance.csv in the result (has_uncertainty, written by
  // `nrsfm reconstruct --uncertainty`): each point's predicted standard
  // deviation PointStd (solvers/uncertainty/uncertainty.h: sqrt(trace Σ_tp)
  // of camera 0's covariance, the same in the object frame), in the units
  // of W; F · P entries (t · P + p), NaN for a point left out.
  bool has_uncertainty = false;
  Eigen::VectorXd point_std;

  // With frames_dir: each frame's image file as a data: URL, F entries.
  std::vector<std::string> frame_images;

  // From result.json when the directory has one.
  bool solution_usable = true;
  std::string start_used;
  std::vector<std::string> warnings;

  // Things the page should say (e.g. that no tracks were given).
  std::vector<std::string> notes;
};

// Reads and checks everything. Fails, naming the path, on a missing result
// directory or one without a valid points_camera.csv / translations.csv, a
// truth or tracks that cannot be read or whose F, P (tracks: F, M, P) differ
// from the result's, a degenerate truth, a skeleton `list` variable that
// is not an n × 2 table of 1-based point indices, and a points_covariance.csv
// that does not hold every (frame, point) of camera 0 once.
Status GatherViewData(const ViewDataOptions& options, ViewData* data);

}  // namespace tools
}  // namespace nrsfm

#endif  // NRSFM_TOOLS_VIEW_DATA_H_
