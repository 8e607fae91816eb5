// How well the data determine a reconstruction: the covariance of each
// camera-frame point and each rotation from the Gauss–Newton information
// matrix of the one Ceres problem at the solution (docs/uncertainty.md).
//
//   Σ_θ = σ² (JᵀJ)⁻¹ over the free parameters θ of the problem that
//   `problem` describes (data term with its weights and robust loss, every
//   extra term at its λ), the gauge fixed explicitly: the rotation block of
//   the first view, the weights of K frames (the pivots of a column-pivoted
//   QR of the weights) and the basis block of the most observed point are
//   held. X̃_tcp, the point of points_camera centred over its frame's points
//   (what nrsfm evaluate compares), and the rotations with the mean over the
//   views of their body-frame perturbation removed are invariant to every
//   continuous gauge of the data term (docs/model.md), so their covariance
//   does not depend on that choice. A term that is not gauge-invariant makes
//   Σ the covariance given the gauge at its value. A perspective model's
//   further gauges (each frame's scale, the basis shift) are the blocks its
//   problem holds constant (every depth, the most observed point's basis:
//   problems/problem_builder.h): Σ is given each frame's scale.
//
// The inverse is never formed: the frames' (ω, T, l, s per frame) and the
// points' (b_p) parameters are split, the larger side is factored sparsely
// (temporal or smoothness couplings included) and eliminated, the smaller
// side's Schur complement is inverted densely, and only the blocks the
// points and rotations need are read: the larger side's own blocks from the
// selected inverse of its factor (solvers/uncertainty/selected_inverse.h).
// Time ~ n_large · n_small², memory 2 · n_large · n_small doubles.
#ifndef NRSFM_SOLVERS_UNCERTAINTY_UNCERTAINTY_H_
#define NRSFM_SOLVERS_UNCERTAINTY_UNCERTAINTY_H_

#include <Eigen/Core>
#include <vector>

#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"
#include "problems/problem_options.h"

namespace nrsfm {

struct UncertaintyOptions {
  // σ, the standard deviation of the observation noise per image coordinate,
  // input units; 0 = estimated from the fit,
  //   σ̂² = Σ_obs w_obs ρ(||e||²) / (N − n),
  // N = 2 × the observations with a residual, n = the free parameters after
  // the gauge. ≥ 0.
  double noise_std = 0.0;
  // The smaller side's parameters are inverted as one dense matrix: more
  // than this many is an error (memory n² doubles, time n_large · n²). ≥ 1.
  int max_dense_parameters = 6000;
  // The two dense n_large × n_small matrices may take at most this many
  // bytes. ≥ 1.
  double max_bytes = 3.0 * (1 << 30);
  // Threads of the dense products and solves (the result is the same for
  // any count). ≥ 1.
  int num_threads = 1;
  Status Check() const;  // names the bad field
};

struct Uncertainty {
  double noise_std = 0.0;        // σ used, input units
  bool noise_estimated = false;  // from the fit (options.noise_std = 0)
  int num_residuals = 0;         // N of the data term
  int num_parameters = 0;        // n free after the gauge
  int gauge_size = 0;            // columns held for the gauge
  // Σ of X̃_tcp (input units²), camera c's frame as points_camera:
  // points[View(t, c) · P + p]. Every point of a frame, seen or not.
  std::vector<Eigen::Matrix3d> points;
  // Σ of the body-frame rotation perturbation δ_tc (R_tc exp([δ]×)) with the
  // mean over all views removed, radians², per view.
  std::vector<Eigen::Matrix3d> rotations;
  double seconds = 0.0;  // wall time
};

// The covariances of `model`, a solution of the problem that `problem`
// describes on `measurements` (every value finite: leave out what a
// reconstruction left out first). Errors on invalid options, a perspective
// model (not covered), a problem that cannot be built, sizes beyond the
// options' limits, no degrees of freedom left for σ̂, and an information
// matrix that is singular beyond the gauge (the data and terms do not
// determine every parameter; the message says which side).
Status ComputeUncertainty(const UncertaintyOptions& options,
                          const ProblemOptions& problem,
                          const Measurements& measurements, const Model& model,
                          Uncertainty* uncertainty);

// A point's standard deviation: sqrt(trace Σ), the RMS 3D distance of the
// estimate from its mean.
double PointStd(const Eigen::Matrix3d& covariance);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_UNCERTAINTY_UNCERTAINTY_H_
