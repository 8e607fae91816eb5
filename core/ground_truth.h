// 3-D ground truth per frame, in the frame of camera 0 (what the metrics of
// DESIGN.md §4 compare with Model::ShapeInCamera(t, 0)).
#ifndef NRSFM_CORE_GROUND_TRUTH_H_
#define NRSFM_CORE_GROUND_TRUTH_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/status.h"

namespace nrsfm {

struct GroundTruth {
  // F entries, 3 × P each: the points of frame t in camera 0's frame, in the
  // units of the measurements W.
  std::vector<Eigen::Matrix3Xd> points_in_camera;
  // Where the truth came from: "S+Rs", "P3_gt", "X" or "points_camera.csv".
  std::string source;

  int NumFrames() const { return static_cast<int>(points_in_camera.size()); }
  int NumPoints() const {
    return points_in_camera.empty()
               ? 0
               : static_cast<int>(points_in_camera[0].cols());
  }
};

// Reads the ground truth of a .mat file from `variable`, or, when it is "",
// from the first that exists of
//   S + Rs  S: 3F × P, world frame, rows x_t, y_t, z_t interleaved;
//           Rs: 2F × 3, rows r1_t, r2_t of the camera (W_t = Rs_t S_t).
//           Camera-frame truth X_t = [r1_t; r2_t; r1_t × r2_t] S_t.
//           The Akhter et al. files also hold `scale`, by which their W and S
//           were divided; it is NOT applied: the truth stays in W's units.
//   P3_gt   3F × P, block layout [x rows; y rows; z rows], camera frame.
//   X       3 × P × F (a 3 × P matrix is one frame), camera frame.
// `variable` may be "S" (needs Rs), "P3_gt" or "X". Fails, naming file and
// variable, on the errors of ReadMatVariable, wrong shapes, Rs rows ≠ 2/3 of
// S rows, non-finite values, and when no truth variable exists.
Status ReadGroundTruth(const std::string& path, const std::string& variable,
                       GroundTruth* truth);

}  // namespace nrsfm

#endif  // NRSFM_CORE_GROUND_TRUTH_H_
