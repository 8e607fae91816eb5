// 3-D shapes per frame for evaluation (core/eval/metrics.h): the ground truth,
// or a reconstruction read back or taken from a Model.
#ifndef NRSFM_CORE_IO_GROUND_TRUTH_H_
#define NRSFM_CORE_IO_GROUND_TRUTH_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/model/status.h"

namespace nrsfm {

struct GroundTruth {
  // F entries, 3 × P each: the points of frame t in camera 0's frame, in the
  // units of the measurements W.
  std::vector<Eigen::Matrix3Xd> points_in_camera;
  // The object frame, when the source has it (empty otherwise): F shapes
  // 3 × P (the world-frame S of the Akhter et al. files; S_t of a
  // reconstruction) and F rotations R_t (camera 0 from object, det +1), with
  // points_in_camera[t] = R_t points_in_object[t] up to a per-frame
  // translation (and, for a reconstruction of several cameras, camera 0's
  // scale s = 1).
  std::vector<Eigen::Matrix3Xd> points_in_object;
  std::vector<Eigen::Matrix3d> rotations;
  // Where the shapes came from: "S+Rs", "P3_gt", "X", "points_camera.csv",
  // "result" (a result directory with its object frame) or "model".
  std::string source;

  // True when points_in_object and rotations hold F entries each.
  bool HasObjectFrame() const {
    return !points_in_object.empty() &&
           points_in_object.size() == points_in_camera.size() &&
           rotations.size() == points_in_camera.size();
  }

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
//           Camera-frame truth X_t = [r1_t; r2_t; r1_t × r2_t] S_t; the
//           object frame is S (points_in_object) with those rotations.
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

#endif  // NRSFM_CORE_IO_GROUND_TRUTH_H_
