// Model: what a reconstruction recovers (docs/model.md).
//
//   S_t      = sum_k l_tk S_k                        (3 × P, object frame)
//   X_tc     = s_tc · R_tc · S_t                     (3 × P, camera c frame)
//   w_tcp    = Π X_tc[:, p] + T_tc,  Π = [I_2 0]     (2D projection)
//
// Storage is chosen so that every Ceres parameter block is one contiguous
// column (Eigen matrices are column-major):
//   rotations     3 × (F·M)  column View(t, c) = angle-axis of R_tc
//                            (rotation_cam_from_object, radians)
//   translations  2 × (F·M)  column View(t, c) = T_tc (input units)
//   weights       K × F      column t = l_t
//   basis         3K × P     column p = b_p = [S_1[:,p]; …; S_K[:,p]]
//   scales        1 × (F·M)  s_tc; camera 0 has s = 1 (monocular: the
//                            projection scale is absorbed in l_t)
//   rig_rotations 3 × (M−1)  angle-axis of the fixed relative rotation
//                            R_c R_0ᵀ of camera c ≥ 1 (rigidity term)
//   rig_scales    1 × (M−1)  fixed scale ratio s_c / s_0 of camera c ≥ 1
//   depths        1 × (F·M)  t_z,tc (perspective; zeros otherwise)
//   intrinsics    4 × M      (fx, fy, cx, cy) of camera c (perspective only)
#ifndef NRSFM_CORE_MODEL_MODEL_H_
#define NRSFM_CORE_MODEL_MODEL_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/model/status.h"

namespace nrsfm {

// How a view projects its camera-frame points (docs/camera.md).
enum class CameraModel {
  kWeakPerspective,  // scaled orthographic: w = s Π R S + T
  kPerspective,      // calibrated pinhole: w = π(R S + [T; t_z])
};
// "weak_perspective" | "perspective"; the error lists them.
const char* CameraModelName(CameraModel camera);
Status ParseCameraModel(const std::string& name, CameraModel* camera);

struct Model {
  int num_frames = 0;   // F
  int num_cameras = 1;  // M
  int num_points = 0;   // P
  int num_bases = 0;    // K

  Eigen::Matrix3Xd rotations;
  Eigen::Matrix2Xd translations;
  Eigen::MatrixXd weights;
  Eigen::MatrixXd basis;
  Eigen::RowVectorXd scales;
  Eigen::Matrix3Xd rig_rotations;
  Eigen::RowVectorXd rig_scales;
  CameraModel camera = CameraModel::kWeakPerspective;
  Eigen::RowVectorXd depths;
  Eigen::Matrix4Xd intrinsics;

  // Allocates every block for the given sizes: identity rotations, zero
  // translations, zero weights and basis, unit scales.
  void Resize(int frames, int cameras, int points, int bases);

  int View(int frame, int camera) const { return frame * num_cameras + camera; }
  int NumViews() const { return num_frames * num_cameras; }

  // R_tc as a 3 × 3 matrix, and its setter (stores the angle-axis).
  Eigen::Matrix3d Rotation(int frame, int camera) const;
  void SetRotation(int frame, int camera, const Eigen::Matrix3d& rotation);

  // Basis shape k (3 × P).
  Eigen::Matrix3Xd BasisShape(int k) const;
  void SetBasisShape(int k, const Eigen::Matrix3Xd& shape);

  // S_t, 3 × P, object frame.
  Eigen::Matrix3Xd ShapeInObject(int frame) const;
  // X_tc, 3 × P, camera frame: s_tc R_tc S_t (weak perspective: no
  // translation), R_tc S_t + [T_tc; t_z,tc] (perspective).
  Eigen::Matrix3Xd ShapeInCamera(int frame, int camera) const;
  // The image points w_tcp of the model above, 2 × P.
  Eigen::Matrix2Xd Project(int frame, int camera) const;

  // Re-expresses weights and basis in the gauge where the mean of the
  // weights over the frames is e_1 (l_t -> A l_t, basis -> A^-T basis), so
  // basis shape 1 is the mean shape (1/F) Σ_t S_t; every S_t is unchanged.
  // Frames whose weights are NaN (left out) are not counted. Returns false
  // (and changes nothing) when the mean weights are zero or not finite.
  bool MakeFirstBasisTheMean();

  // Checks that every block has the size Resize() gives and finite values;
  // a perspective model needs 4 × M intrinsics with fx, fy > 0.
  // With allow_nan, NaN is accepted (never ±Inf): the mark of a point or
  // frame left out of a reconstruction (solvers/pipeline/drop_unobserved.h).
  Status Validate(bool allow_nan = false) const;
};

// The model with `num_bases` (1 ≤ K' ≤ K) basis shapes whose shape sequence
// is the best rank-K' approximation of `model`'s in the object frame: the
// truncated SVD of the F × 3P matrix with row t = S_t (column-major), its
// first K' right singular vectors as the basis shapes, U Σ as the weights.
// Rotations, translations, scales and the rig are kept. Frames whose weights
// are not finite (left out) are left out of the SVD and keep NaN weights.
// The camera-frame shapes change only by what the truncation drops.
Model ReduceNumBases(const Model& model, int num_bases);

}  // namespace nrsfm

#endif  // NRSFM_CORE_MODEL_MODEL_H_
