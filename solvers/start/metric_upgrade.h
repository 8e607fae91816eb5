// Metric upgrade of an affine factorisation (Bregler et al. 2000;
// Tomasi-Kanade 1992, weak-perspective form; docs/factorization.md,
// section 3).
//
// Input: N blocks M_n (2 × 3, rows m₁, m₂), each an unknown scale c_n times
// the first two rows of a rotation seen through one common 3 × 3 gauge:
//   M_n G = c_n Π R_n,   R_n ∈ SO(3).
// With H = G Gᵀ (symmetric, 6 unknowns) orthonormality of the rows of Π R_n
// gives two homogeneous linear equations per block (the scale c_n is free, so
// the footnote's "= 1" becomes "equal norms"):
//   m₁ H m₁ᵀ − m₂ H m₂ᵀ = 0,   m₁ H m₂ᵀ = 0.
// Each block is first scaled to unit Frobenius norm (every frame weighs the
// same). The least-squares h is the right singular vector of the 2N × 6
// equation matrix E for its smallest singular value, scaled so that
// mean_n (m₁ H m₁ᵀ + m₂ H m₂ᵀ) / 2 = 1 (a global scale; it fixes the sign).
// Noise can leave H indefinite; it is then replaced by the nearest positive
// definite matrix in the sense of the symmetric eigen-decomposition: every
// eigenvalue is clamped to at least kMinEigenvalueFraction of the largest,
// and `was_indefinite` is set. G = H^{1/2} (the symmetric square root; any
// G U with U orthogonal is equivalent: the global rotation gauge).
#ifndef NRSFM_SOLVERS_START_METRIC_UPGRADE_H_
#define NRSFM_SOLVERS_START_METRIC_UPGRADE_H_

#include <Eigen/Core>

#include "core/math/svd.h"
#include "core/model/status.h"

namespace nrsfm {

struct MetricUpgrade {
  Eigen::Matrix3d h = Eigen::Matrix3d::Identity();  // G Gᵀ (after any clamping)
  Eigen::Matrix3d g = Eigen::Matrix3d::Identity();  // symmetric H^{1/2}
  bool was_indefinite = false;  // H had an eigenvalue below the clamp
  // σ₅ / σ₁ of E: how well the equations determine H up to scale (1-D null
  // space wanted); 0 when the blocks carry no rotation information.
  double conditioning = 0.0;
};

// Smallest eigenvalue of H kept, relative to its largest, when H is indefinite.
constexpr double kMinEigenvalueFraction = 1e-2;
// Below this conditioning the blocks do not determine H: the sequence shows
// (numerically) no rotation.
constexpr double kMinMetricConditioning = 1e-6;

// Below this ratio σ₃ / σ₁ of the centred tracks the rigid component has
// rank < 3: no rotation in the sequence (or a flat object), depth is
// unobservable.
constexpr double kMinThirdSingularValueRatio = 1e-6;

// Checks σ₃ ≥ kMinThirdSingularValueRatio · σ₁ for the singular values (in
// decreasing order) of the centred 2F × P tracks; the error says why depth
// is then unobservable. Noise hides this case (σ₃ is then the noise level);
// the conditioning test of SolveMetricUpgrade is the second guard.
Status CheckRotationObservable(const Eigen::VectorXd& singular_values);

// The SVD of the centred 2F × P tracks `w` that the factorization and rigid
// starts upgrade: ComputeTopSvd(w, min(3K, 2F, P), kBoth). One function for
// a start's own SVD and the starts' shared one (StartCache,
// solvers/start/start.h): ComputeTopSvd's vectors depend on the count, so
// both must ask for the same.
ThinSvd StartSvd(const Eigen::MatrixXd& w, int num_bases);

// `blocks` is 2N × 3, rows 2n and 2n + 1 the block M_n (N ≥ 3). Errors when
// the conditioning is below kMinMetricConditioning (no or too little rotation
// in the sequence) or when the normalisation is not positive.
Status SolveMetricUpgrade(const Eigen::MatrixX3d& blocks,
                          MetricUpgrade* upgrade);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_START_METRIC_UPGRADE_H_
