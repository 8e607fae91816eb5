// Thin singular value decompositions of dense matrices, A = U diag(σ) Vᵀ
// with σ in decreasing order: the one owner of Eigen's dense dynamic-size
// SVDs in the library, so that they are compiled once (their compile time is
// measured in docs/performance.md).
#ifndef NRSFM_CORE_MATH_SVD_H_
#define NRSFM_CORE_MATH_SVD_H_

#include <Eigen/Core>

namespace nrsfm {

// Which singular vectors to compute.
enum class SingularVectors { kNone, kLeft, kRight, kBoth };

struct ThinSvd {
  Eigen::VectorXd
      singular_values;  // min(m, n) values (ComputeTopSvd: count), decreasing
  Eigen::MatrixXd u;    // m × min(m, n) with kLeft / kBoth, else empty
  Eigen::MatrixXd v;    // n × min(m, n) with kRight / kBoth, else empty
};

// Divide and conquer (Eigen::BDCSVD), for large matrices (e.g. the 2F × P
// tracks). Eigen itself uses one-sided Jacobi when A has fewer than 16
// columns.
ThinSvd ComputeThinSvd(const Eigen::MatrixXd& a, SingularVectors vectors);

// The `count` largest singular values and their vectors (count columns of u
// and v), 1 ≤ count ≤ min(m, n). For a matrix of 2^20 entries or more of
// which at most a quarter of the spectrum is wanted, they come from the
// short side's Gram matrix (A Aᵀ or AᵀA: matrix products instead of a
// bidiagonalisation, ~6× faster on a 600 × 10 000 matrix): its top
// eigenvectors, two subspace iterations with A itself (A (Aᵀ Q), which
// restore the accuracy the Gram matrix's rounding costs, ε σ_1² /
// (σ_count² − σ_(count+1)²), to within the SVD's own order when the
// spectrum has a gap there) and a Rayleigh-Ritz step (the SVD of the
// count × n projection). Otherwise ComputeThinSvd, truncated (the same bits
// as it): small inputs, where the full SVD is fast, keep its accuracy at
// every gap.
ThinSvd ComputeTopSvd(const Eigen::MatrixXd& a, int count,
                      SingularVectors vectors);

// Two-sided Jacobi (Eigen::JacobiSVD with column-pivoting QR
// preconditioning), for small matrices (e.g. the metric upgrade's 2N × 6
// equations): accurate to the last bits for any size, slow for large ones.
ThinSvd ComputeJacobiSvd(const Eigen::MatrixXd& a, SingularVectors vectors);

}  // namespace nrsfm

#endif  // NRSFM_CORE_MATH_SVD_H_
