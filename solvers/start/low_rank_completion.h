// Affine low-rank completion of a measurement matrix with missing entries
// (docs/factorization.md, section 1).
//
// Model: every row i of W (2·F·M rows, core/model/measurements.h layout) is
//   W[i, p] ≈ a_iᵀ b_p + t_i,   a_i ∈ R^r, b_p ∈ R^r, t_i ∈ R,
// i.e. W ≈ A B + t 1ᵀ, rank r plus a per-row translation (rank r + 1 affine).
// For NRSfM r = 3K: the motion factor Q of W = Q B (docs/factorization.md)
// plus the image translation.
//
// Algorithm (alternating least squares, the "drop the missing rows and solve
// the over-constrained system" of Torresani et al. 2001, applied to each
// factor in turn):
//   0. B from the top r right singular vectors of the mean-filled, row-centred
//      W (visible entries minus the row's visible mean, 0 where missing).
//   1. Given B: each row's [a_i; t_i] by linear least squares over the
//      row's visible columns ((r + 1) unknowns).
//   2. Given A, t: each column's b_p by linear least squares over the
//      column's visible rows (r unknowns).
//   3. Gauge: A B = (A C)(C⁻¹ B) for any invertible C, and a constant
//      added to every b_p moves into t. After step 2 the rows of B are
//      centred (Σ_p b_p = 0, the shift moved into t) and orthonormalised
//      (Bᵀ = Q R, B ← Qᵀ, A ← A Rᵀ), which leaves A B + t 1ᵀ unchanged and
//      keeps both sub-problems well conditioned. With B centred, t_i is the
//      mean over all P columns of the completed row.
//   Ridge: a Gaussian prior on A and B (not on t), σ̂² (the previous round's
//   mean squared residual, floored at (ridge_floor · RMS of the row-centred
//   data)²) · P added to the column solves' diagonal and σ̂² / mean(a_ij²)
//   to the rows': missing entries the pattern barely determines stay near
//   the smallest-norm completion instead of drifting; on noise-free data a
//   bias of about ridge_floor² relative (docs/factorization.md, section 1);
//   ridge_floor = 0 gives an exact fit.
//   Every normal matrix N also gets 1e-12 · tr(N) / n on its diagonal (no
//   Inf/NaN from a rank-deficient row or column).
//   Steps 1-3 repeat until the RMS fit residual over the visible entries
//   decreases by less than 1e-12 of itself (an increase also stops), or
//   falls below 1e-13 of the RMS of the row-centred data, or
//   `max_iterations` is reached.
// On noise-free rank-r affine data whose visible pattern determines the
// completion, the missing entries are recovered up to the ridge bias above
// (ALS converges linearly; the rate depends on the fraction missing).
#ifndef NRSFM_SOLVERS_START_LOW_RANK_COMPLETION_H_
#define NRSFM_SOLVERS_START_LOW_RANK_COMPLETION_H_

#include <Eigen/Core>
#include <mutex>
#include <vector>

#include "core/model/measurements.h"
#include "core/model/status.h"

namespace nrsfm {

struct LowRankCompletionOptions {
  int max_iterations = 500;  // ALS rounds (steps 1-3 above)
  // floor of the ridge's noise RMS, relative to the data RMS, ≥ 0
  double ridge_floor = 5e-4;

  Status Check() const;
};

struct LowRankCompletion {
  // (2·F·M) × P: the visible entries of W unchanged, the missing ones
  // replaced by the fit a_iᵀ b_p + t_i.
  Eigen::MatrixXd completed;
  // 2·F·M: the per-row translation, in W's units. For a view (frame, camera)
  // that sees every point it is the plain mean of its two rows (the
  // Tomasi-Kanade centring); otherwise the affine term t_i of the fit.
  Eigen::VectorXd translations;
  double residual_rms = 0.0;  // RMS of W − (A B + t 1ᵀ) over visible entries
  int iterations = 0;         // ALS rounds run
  bool converged = false;     // stopped by a tolerance, not the limit
};

// Completes `measurements.W` with a rank-`rank` (r ≥ 1; 3K for K basis
// shapes) plus translation fit. Errors on invalid options or r < 1, and
// (naming the row or point) when a view sees fewer than r + 1 points or a
// point is seen in fewer than r rows (⌈r/2⌉ views): its factor would be
// undetermined. The same as FitLowRankAffine then CompleteFromFactors.
// The row and column solves run on up to `num_threads` threads; each is
// solved on its own, so the result does not depend on the thread count.
Status CompleteLowRankAffine(const Measurements& measurements, int rank,
                             const LowRankCompletionOptions& options,
                             LowRankCompletion* completion,
                             int num_threads = 1);

// The fit behind a completion, W ≈ A B + t 1ᵀ, and how its ALS ended: (2FM +
// P) · r numbers where the completed matrix has 2FM · P.
struct LowRankFactors {
  Eigen::MatrixXd a;          // 2FM × r
  Eigen::MatrixXd b;          // r × P, rows centred and orthonormal
  Eigen::VectorXd t;          // 2FM, the affine term
  double residual_rms = 0.0;  // as LowRankCompletion's
  int iterations = 0;
  bool converged = false;
};

// Steps 0-3 of the header; errors and threads as CompleteLowRankAffine's.
Status FitLowRankAffine(const Measurements& measurements, int rank,
                        const LowRankCompletionOptions& options,
                        LowRankFactors* factors, int num_threads = 1);

// The completion of `measurements` from the factors FitLowRankAffine fitted
// to them: bit for bit what CompleteLowRankAffine returns.
void CompleteFromFactors(const Measurements& measurements,
                         const LowRankFactors& factors,
                         LowRankCompletion* completion);

// The completions of one set of measurements, each rank and options fitted
// once and kept as factors (so that the prior rule and every start of a
// reconstruction share them; solvers/pipeline/reconstruct.h). Safe to call from
// several threads: a completion asked for while another thread fits it
// waits for that fit. `measurements` must outlive the memo; the fits run on
// up to `num_threads` threads.
class LowRankCompletionMemo {
 public:
  explicit LowRankCompletionMemo(const Measurements& measurements,
                                 int num_threads = 1)
      : measurements_(measurements), num_threads_(num_threads) {}
  LowRankCompletionMemo(const LowRankCompletionMemo&) = delete;
  LowRankCompletionMemo& operator=(const LowRankCompletionMemo&) = delete;

  // CompleteLowRankAffine(measurements, rank, options, completion), its
  // result and status the same.
  Status Complete(int rank, const LowRankCompletionOptions& options,
                  LowRankCompletion* completion);

 private:
  struct Entry {
    int rank = 0;
    LowRankCompletionOptions options;
    Status status;
    LowRankFactors factors;
  };
  const Measurements& measurements_;
  const int num_threads_;
  std::mutex mutex_;
  std::vector<Entry> entries_;
};

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_START_LOW_RANK_COMPLETION_H_
