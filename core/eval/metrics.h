// Error metrics of a reconstruction against ground truth (docs/metrics.md).
//
// Shapes are camera-frame, one 3 × P matrix per frame, F frames (e.g.
// CameraFrameShapes(model) or the world-frame S / Shat of the Akhter files,
// which share one frame). Column p of every frame is the same point in truth
// and estimate. Every shape metric first centres each frame of both inputs
// (subtracts the mean over its P points), so translations never count.
// Notation: X_t = centred truth of frame t, X̂_t = centred estimate, X_tp its
// column p.
//
// The ComputeX functions CHECK their sizes (same F ≥ 1, same P ≥ 1 per frame;
// a programmer error); EvaluateShapes validates user data and returns a
// Status instead.
#ifndef NRSFM_CORE_EVAL_METRICS_H_
#define NRSFM_CORE_EVAL_METRICS_H_

#include <Eigen/Core>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "core/io/ground_truth.h"
#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"

namespace nrsfm {

// e3D of Akhter et al. (2008, "Nonrigid structure from motion in trajectory
// space"; their compareStructs/findRotation code), the field's standard:
//   s    = (1 / 3F) Σ_rows std_pop(row), the truth stacked as a 3F × P
//          matrix with rows x_t, y_t, z_t and std_pop the population
//          standard deviation (divide by P) of a row over the P points;
//   Y    = NearestOrthogonal(C M⁺), C = Σ_t X_t X̂_tᵀ, M = Σ_t X̂_t X̂_tᵀ:
//          the unconstrained least-squares 3 × 3 map of all frames at once,
//          then its nearest orthogonal matrix (reflection allowed; see
//          AlignLeastSquaresThenOrthogonal in core/math/procrustes.h);
//   e3D  = (1 / F) Σ_t (1 / P) Σ_p ||X_tp − Y X̂_tp|| / s.
// This reproduces PTA's published numbers on the shared data
// (tests/core/eval/metrics_real_data_test.cc); orthogonal Procrustes for Y (SVD
// of C alone) and the sample standard deviation do not (docs/metrics.md).
// Invariant to a global rotation or reflection of the estimate, not to its
// scale. Dimensionless.
double ComputeE3D(const std::vector<Eigen::Matrix3Xd>& truth,
                  const std::vector<Eigen::Matrix3Xd>& estimate);

// ComputeE3D with one global scale as well, for answers fixed only up to
// scale (a monocular perspective answer, docs/camera.md): with X_t, X̂_t
// centred and Y the alignment of ComputeE3D,
//   c = Σ_t ⟨X_t, Y X̂_t⟩ / Σ_t ||Y X̂_t||²  (least squares),
// the e3D of c · Y X̂_t. c is the least-squares scale, not the
// e3D-minimising one, so an estimate already at the truth's scale can score
// a little above ComputeE3D. Same CHECKs.
double ComputeScaledE3D(const std::vector<Eigen::Matrix3Xd>& truth,
                        const std::vector<Eigen::Matrix3Xd>& estimate);

// The parts of ComputeE3D for display: the alignment Y (truth ≈ Y · centred
// estimate), s, and each frame's (1 / P) Σ_p ||X_tp − c Y X̂_tp|| / s, whose
// mean is e3D (c = 1), or with `with_scale` ComputeScaledE3D (c its
// least-squares scale, estimate_scale). Same CHECKs as ComputeE3D.
struct E3DDetail {
  Eigen::Matrix3d alignment = Eigen::Matrix3d::Identity();
  double scale = 0.0;
  double estimate_scale = 1.0;  // c
  std::vector<double> frame_errors;
};
E3DDetail ComputeE3DDetail(const std::vector<Eigen::Matrix3Xd>& truth,
                           const std::vector<Eigen::Matrix3Xd>& estimate,
                           bool with_scale = false);

// The rank-K floor of e3D: ComputeE3D(truth, X̂) of the best rank-K
// approximation X̂ of the centred truth itself (the truncated SVD of the
// F × 3P matrix with row t = X_t, column-major), which no sequence of
// S_t = Σ_k l_tk S_k with K bases can score below in the frame of `truth`
// (use it with object-frame truth: the world-frame S of the Akhter et al.
// files). CHECKs F ≥ 1 and equal P; K ≥ 1 (K ≥ min(F, 3P) gives 0).
double ComputeRankFloorE3D(const std::vector<Eigen::Matrix3Xd>& truth,
                           int num_bases);

// Relative Frobenius error with a per-frame depth sign (Lee et al., the metric
// used for the face sequence):
//   e = (1 / F) Σ_t min(||X_t − X̂_t||_F, ||X_t − Z X̂_t||_F) / ||X_t||_F,
//   Z = diag(1, 1, −1).
// No rotation alignment at all: truth and estimate are compared directly in
// the camera frame (x, y are fixed by the image; only the depth sign of each
// frame is ambiguous), as in the literature for this metric. Dimensionless;
// a flat estimate (z = 0) scores ||z_t|| / ||X_t|| per frame.
double ComputeFrobeniusZSign(const std::vector<Eigen::Matrix3Xd>& truth,
                             const std::vector<Eigen::Matrix3Xd>& estimate);

// Size of a shape sequence, the denominator of the % errors below: the mean
// over frames of the truth's diameter, the largest distance between two of
// its points (rotation and translation invariant); points with a non-finite
// coordinate (left out) are not counted. Exact; pairs that cannot be the
// longest are skipped (its time: docs/performance.md).
double ShapeSize(const std::vector<Eigen::Matrix3Xd>& truth);

// 3D error in % of shape size (Torresani et al. 2001): with Y the e3D alignment
// above,
//   100 · (1 / FP) Σ_t Σ_p ||X_tp − Y X̂_tp|| / ShapeSize(truth).
double ComputeError3DPercent(const std::vector<Eigen::Matrix3Xd>& truth,
                             const std::vector<Eigen::Matrix3Xd>& estimate);

// z (depth) error in % of shape size (Torresani et al. 2001): with the same Y,
//   100 · (1 / FP) Σ_t Σ_p |z_tp − (Y X̂_tp)_z| / ShapeSize(truth).
double ComputeZErrorPercent(const std::vector<Eigen::Matrix3Xd>& truth,
                            const std::vector<Eigen::Matrix3Xd>& estimate);

// Rotation error of Dai, Li and He (their BMM code's compareRotations): the
// first two rows of every rotation stacked into 2F × 3 matrices A (truth) and
// Â (estimate); one orthogonal Q = argmin ||Â Q − A||_F (reflection allowed:
// the depth-reflected reconstruction scores the same);
//   error = (1 / F) Σ_t ||Â_t Q − A_t||_2,
// the spectral norm of each frame's 2 × 3 difference. For small errors it is
// the mean rotation error in radians. CHECKs equal, non-zero lengths.
double ComputeRotationError(const std::vector<Eigen::Matrix3d>& truth,
                            const std::vector<Eigen::Matrix3d>& estimate);

// Which frame the field's e3D is computed in (docs/metrics.md): the object
// frame when the truth has one (world-frame S
// with camera rotations Rs, as in the Akhter et al. files: the published
// numbers of PTA and of Dai et al.'s BMM code, rotStruct = 0, compare the
// reconstruction's object-frame shapes S_t with the world-frame S, so the
// recovered rotations count), the camera frame otherwise (P3_gt, X, a
// points_camera.csv).
enum class EvaluationFrame { kObject, kCamera };
const char* EvaluationFrameName(EvaluationFrame frame);  // "object" | "camera"

struct ShapeErrors {
  // ComputeE3D in `e3d_frame`: the number to compare with published e3D.
  double e3d = 0.0;
  EvaluationFrame e3d_frame = EvaluationFrame::kCamera;
  double e3d_camera = 0.0;  // ComputeE3D of the camera-0 frame shapes
  // ComputeScaledE3D in `e3d_frame`: the number for a perspective answer.
  double e3d_scaled = 0.0;
  // Camera frame (camera 0), whatever the truth:
  double frob_zsign = 0.0;   // ComputeFrobeniusZSign
  double error3d_pct = 0.0;  // ComputeError3DPercent, %
  double zerror_pct = 0.0;   // ComputeZErrorPercent, %
  // ComputeRotationError of camera 0 when truth and estimate both have
  // rotations; NaN otherwise.
  double rotation_error = std::numeric_limits<double>::quiet_NaN();
  int num_frames = 0;  // F
  int num_points = 0;  // P
  // Frames and points the estimate holds as NaN (left out of a
  // reconstruction), 0-based; the errors above are of the others.
  std::vector<int> unscored_frames;
  std::vector<int> unscored_points;
};

// All of the above, after checking user data: same F ≥ 1 in both, the same
// P ≥ 1 in every frame of both, finite values, and a truth that is not
// degenerate (no frame whose points all coincide). Errors name the frame.
// The object-frame e3D is used when truth.HasObjectFrame(); the estimate must
// then have its object frame too (an error says so otherwise). Every shape is
// centred per frame before it is compared.
// NaN in the estimate marks what a reconstruction left out: a frame whose
// points are all NaN and a point NaN in any other frame are not scored
// (errors->unscored_frames / unscored_points list them; num_frames and
// num_points stay those of the sequence); an error when that is every frame
// or every point. NaN in the truth, and ±Inf anywhere, are errors.
Status EvaluateShapes(const GroundTruth& truth, const GroundTruth& estimate,
                      ShapeErrors* errors);

// The metrics of `errors` under the one set of names that result.json,
// `nrsfm evaluate`, `nrsfm view` and the benchmarks use, in this order: e3d,
// e3d_camera, frob_zsign, error3d_pct, zerror_pct, and rotation_error when it
// was computed (not NaN).
std::vector<std::pair<std::string, double>> MetricList(
    const ShapeErrors& errors);

// The two sequences EvaluateShapes compares for the e3D of `errors.e3d_frame`:
// the object-frame shapes for EvaluationFrame::kObject, the camera frame
// otherwise.
const std::vector<Eigen::Matrix3Xd>& ScoredShapes(const GroundTruth& shapes,
                                                  EvaluationFrame frame);

// The shapes of a model for EvaluateShapes: camera `camera`'s frame
// (Model::ShapeInCamera), the object frame S_t and the rotations R_tc.
GroundTruth ShapesOfModel(const Model& model, int camera = 0);

// Reprojection RMS over the visible entries, in the units of W: the RMS of the
// 2D point distance,
//   sqrt( (1 / N) Σ_{visible (t,c,p)} ||w_tcp − model.Project(t, c)[:, p]||² ),
// N the number of visible observations. NaN when nothing is visible. CHECKs
// that F, M and P of the two agree. The views are projected on up to
// `num_threads` threads; the result is the same bits for any count.
double ReprojectionRms(const Measurements& measurements, const Model& model,
                       int num_threads = 1);

// The sum under the root of ReprojectionRms,
//   Σ_{visible (t,c,p)} ||w_tcp − model.Project(t, c)[:, p]||²,
// in squared units of W (0 when nothing is visible). Same CHECKs and threads.
double ReprojectionSquaredError(const Measurements& measurements,
                                const Model& model, int num_threads = 1);

// ReprojectionRms of reprojections given as a matrix in the layout of
// Measurements::W ((2FM) × P, e.g. read back from a result directory), per
// frame and over all: frame_rms(t) over the visible entries of frame t (all
// its cameras; NaN when none is visible), rms over every visible entry (NaN
// when none). CHECKs the size of `reprojections`.
struct FrameReprojectionRms {
  Eigen::VectorXd frame_rms;  // F entries, units of W
  double rms = 0.0;           // units of W
};
FrameReprojectionRms ComputeFrameReprojectionRms(
    const Measurements& measurements, const Eigen::MatrixXd& reprojections);

// Camera-frame shapes X_tc = model.ShapeInCamera(t, camera) of every frame,
// 3 × P each (no translation).
std::vector<Eigen::Matrix3Xd> CameraFrameShapes(const Model& model,
                                                int camera = 0);

}  // namespace nrsfm

#endif  // NRSFM_CORE_EVAL_METRICS_H_
