// Entries of the inverse of a sparse symmetric positive definite matrix on
// the pattern of its Cholesky factor (Takahashi, Fagan and Chen 1973): the
// marginal covariance blocks of a sparse information matrix without the
// dense inverse. With H = Pᵀ L D Lᵀ P (Eigen's SimplicialLDLT, L unit lower),
// Z = (L D Lᵀ)⁻¹ satisfies, for j from n − 1 down to 0 and i in the pattern
// of column j of L,
//   Z_ij = − Σ_{k ∈ col j of L} L_kj Z_ik,   Z_jj = 1/d_j − Σ_k L_kj Z_kj,
// and every Z_ik it reads lies in the same pattern (the factor's pattern is
// chordal). Cost Σ_j |col j|² (log of a column's length for each lookup); a
// block-banded H of bandwidth w costs n w².
#ifndef NRSFM_SOLVERS_UNCERTAINTY_SELECTED_INVERSE_H_
#define NRSFM_SOLVERS_UNCERTAINTY_SELECTED_INVERSE_H_

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

namespace nrsfm {

class SelectedInverse {
 public:
  // `ldlt` must hold a successful factorisation (info() == Success) of an n ×
  // n matrix H; it is only read here.
  explicit SelectedInverse(
      const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>& ldlt);

  // (H⁻¹)_ij for rows and columns of H (its own numbering). CHECKs that the
  // entry lies in the computed pattern: every (i, j) with H_ij ≠ 0 does (so
  // every entry of a block that H holds densely, e.g. a frame's or a point's
  // own block).
  double operator()(int i, int j) const;

 private:
  // Z in the permuted numbering, lower triangle on L's pattern (CSC), and
  // its diagonal.
  Eigen::SparseMatrix<double> lower_;
  Eigen::VectorXd diagonal_;
  Eigen::VectorXi permutation_;       // row of H → row of P H Pᵀ
  double Lookup(int i, int j) const;  // permuted, i ≠ j
};

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_UNCERTAINTY_SELECTED_INVERSE_H_
