// Measurements: the 2D point tracks of a deforming object, seen by one camera
// (monocular) or by M synchronised cameras (docs/model.md).
//
// Layout: W is (2·F·M) × P. Frame t, camera c occupies rows
//   2·(t·M + c)     : u (x image coordinate) of every point,
//   2·(t·M + c) + 1 : v (y image coordinate).
// With M = 1 this is the usual interleaved 2F × P tracking matrix.
// `visible` is (F·M) × P: visible(t·M + c, p) says whether point p was observed
// by camera c at frame t. Entries of W that are not visible are ignored by
// every algorithm (their value is unspecified; readers store NaN there).
#ifndef NRSFM_CORE_MODEL_MEASUREMENTS_H_
#define NRSFM_CORE_MODEL_MEASUREMENTS_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/model/status.h"

namespace nrsfm {

using VisibilityMask = Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic>;

struct Measurements {
  int num_frames = 0;      // F
  int num_cameras = 1;     // M
  int num_points = 0;      // P
  Eigen::MatrixXd W;       // (2·F·M) × P, see the layout above.
  VisibilityMask visible;  // (F·M) × P.
  // The input's own index of each frame and point, when the reader numbered
  // them otherwise: an observation list too sparse for a W over all its
  // indices keeps only the frames and points it mentions, in increasing
  // order (core/io/text_io.h). Empty (the usual case): frame t and point p are
  // the input's t and p. Otherwise of size F and P, strictly increasing.
  std::vector<int> frame_ids;
  std::vector<int> point_ids;
  // Pinhole intrinsics of each camera when known (a .mat file's Kcam, or
  // given): column c = (fx, fy, cx, cy) of camera c, input units (pixels),
  // u = fx x / z + cx, v = fy y / z + cy. Empty (4 × 0) when unknown; only
  // the perspective camera model uses them (docs/camera.md).
  Eigen::Matrix4Xd intrinsics = Eigen::Matrix4Xd(4, 0);

  // Index of the (frame, camera) pair: the row of `visible`, the column of
  // Model::rotations / translations.
  int View(int frame, int camera) const { return frame * num_cameras + camera; }
  int NumViews() const { return num_frames * num_cameras; }
  // First of the two rows of W of (frame, camera).
  int Row(int frame, int camera) const { return 2 * View(frame, camera); }

  // The observation of point p in (frame, camera); only meaningful if visible.
  Eigen::Vector2d Observation(int frame, int camera, int point) const {
    const int row = Row(frame, camera);
    return Eigen::Vector2d(W(row, point), W(row + 1, point));
  }

  int NumVisible() const;
  // Number of visible points per view (size F·M) and per point (size P).
  Eigen::VectorXi VisiblePerView() const;
  Eigen::VectorXi VisiblePerPoint() const;
  bool IsComplete() const { return visible.all(); }
  // The spread of the data, the scale of reprojection errors: the RMS
  // distance of the visible observations from the centroid of their view's
  // visible observations, in input units (0 when nothing is visible).
  double ImageSpreadRms() const;

  // Builds measurements from a (2·F·M) × P matrix where NaN marks a missing
  // entry. Both coordinates of an observation must be NaN or both finite.
  // `name` is used in messages (e.g. "drink.mat: W"). Fails on ±Inf, on one
  // NaN coordinate of a pair, on a row count that is not a multiple of 2·M.
  static Status FromMatrixWithNaN(const Eigen::MatrixXd& w, int num_cameras,
                                  const std::string& name,
                                  Measurements* measurements);

  // Checks sizes and values: F ≥ 1, M ≥ 1, P ≥ 1, matching W and mask sizes,
  // finite visible entries, frame_ids and point_ids empty or of size F and P
  // and strictly increasing from 0 up, intrinsics empty or 4 × M, finite,
  // with fx, fy > 0. Does not judge whether the data can be
  // reconstructed (see the solvers for that).
  Status Validate() const;
};

}  // namespace nrsfm

#endif  // NRSFM_CORE_MODEL_MEASUREMENTS_H_
