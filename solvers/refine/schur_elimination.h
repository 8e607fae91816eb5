// The exact elimination of the point blocks from the Levenberg–Marquardt
// system (JᵀJ + μD) δ = −g (solvers/refine/structured_solver.h), with J = [J_f
// J_p] split into the reduced (frame and shared) and eliminated (point) columns
// of solvers/refine/structured_layout.h:
//   C̃ = J_pᵀ J_p + μ D_p, block-diagonal when no residual block holds two
//       points, else block-sparse with a block (i, j) per pair of points that
//       a residual couples (Residual::coupled, or a grid's column of several
//       points: the Delaunay smoothness term),
//   S = J_fᵀ J_f + μ D_f − J_fᵀ J_p C̃⁻¹ J_pᵀ J_f (the Schur complement),
//   S δ_f = −g_f + J_fᵀ J_p C̃⁻¹ g_p,   δ_p = C̃⁻¹ (−g_p − J_pᵀ J_f δ_f).
// S is never formed: ApplyReduced() multiplies by it with two passes over
// the residual blocks in the order their Jacobians are stored (the
// reprojection residuals as one panel when StructuredJacobian::uses_panel(),
// solvers/refine/reprojection_panel.h); ReducedRightHandSide() is the second
// pass alone and BackSubstitute() the first. C̃⁻¹ is applied by one Cholesky
// factor per point, or, when residuals couple points, by one sparse Cholesky
// factor of C̃ (SuiteSparse's CHOLMOD, supernodal, through Eigen's
// CholmodSupernodalLLT; its ordering and pattern analysed once, messages off):
// the couplings follow a sparse graph (the smoothness stencils join each point
// to its Delaunay neighbours' neighbours), so the factor stays sparse, and its
// supernodes are dense blocks (docs/performance.md: 8 times faster than a
// simplicial factor at P 2 000).
//
// Assumes the StructuredJacobian holds the Jacobian of the current values;
// ComputeGram() after every Evaluate(true), Factor() for every μ. The same
// bits for any thread count (each point's blocks are its own; the sums are
// StructuredJacobian's; the couplings' blocks are added and factored on one
// thread).
#ifndef NRSFM_SOLVERS_REFINE_SCHUR_ELIMINATION_H_
#define NRSFM_SOLVERS_REFINE_SCHUR_ELIMINATION_H_

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "solvers/refine/structured_jacobian.h"
#include "solvers/refine/structured_layout.h"

namespace nrsfm {
namespace structured {

class SchurElimination {
 public:
  // `blocks` and `jacobian` must outlive this.
  SchurElimination(const StructuredBlocks& blocks,
                   const StructuredJacobian& jacobian, int num_threads);
  ~SchurElimination();

  // J_pᵀ J_p per eliminated block (and per coupled pair), from the current
  // Jacobian.
  void ComputeGram();
  // Cholesky of C̃ = J_pᵀ J_p + μ D_p per eliminated block, or of the whole
  // C̃ when points are coupled (d_eliminated: the diagonal D_p, one value per
  // eliminated column).
  void Factor(double mu, const Eigen::VectorXd& d_eliminated);
  // Per grid g of StructuredBlocks::grids, H_g = M (Σ_e s_e² D_eᵀ D_e) M
  // (K × K, M = diag(m)): J_fᵀJ_f of grid g's residuals in each row is
  // σ_a σ_b H_g between the row's weights blocks a and b, from the last
  // ComputeGram().
  const std::vector<Eigen::MatrixXd>& grid_grams() const { return grid_gram_; }
  // Adds the grids' residuals' part of diag(JᵀJ), which
  // StructuredJacobian::ColumnSquaredNorms leaves out, from the last
  // ComputeGram()'s sums: residual (q, e) is s_e D_e λ_q, so a weights block
  // of row q with sign σ gets σ² diag(H_g) and a basis block of column e
  // with sign τ gets s_e² τ² Σ_q λ_qk² in its 3 columns of basis shape k.
  void AddGridColumnSquaredNorms(Eigen::VectorXd* reduced,
                                 Eigen::VectorXd* eliminated) const;
  // out = C̃⁻¹ in (eliminated columns).
  void SolveEliminated(const Eigen::VectorXd& in, Eigen::VectorXd* out) const;
  // out = S v (reduced columns), D_f = diag(d_reduced).
  void ApplyReduced(const Eigen::VectorXd& v, double mu,
                    const Eigen::VectorXd& d_reduced,
                    Eigen::VectorXd* out) const;
  // rhs = −g_f + J_fᵀ J_p C̃⁻¹ g_p.
  void ReducedRightHandSide(const Eigen::VectorXd& gradient_reduced,
                            const Eigen::VectorXd& gradient_eliminated,
                            Eigen::VectorXd* rhs) const;
  // step_eliminated = C̃⁻¹ (−g_p − J_pᵀ J_f step_reduced).
  void BackSubstitute(const Eigen::VectorXd& step_reduced,
                      const Eigen::VectorXd& gradient_eliminated,
                      Eigen::VectorXd* step_eliminated) const;

 private:
  using SparseMatrix = Eigen::SparseMatrix<double>;

  // The lower triangle of C̃'s pattern, column-major: per eliminated block
  // column k, its diagonal block's lower part, then the blocks of the
  // coupled points i > k in order.
  void BuildCoupledPattern();
  // Adds the coupling residuals' J_aᵀ J_b to gram_ (a = b) and
  // coupled_gram_ (grids' residuals: AddGridGram).
  void AddCouplingGram();
  // The block J_aᵀ J_b of C̃ for eliminated positions a ≠ b (coupled_).
  Eigen::MatrixXd& CoupledGram(int a, int b);
  // Grid g's part of C̃ (τ_i τ_j s_e² G ⊗ I₃ per pair of a column's points,
  // G = Σ_q λ_q λ_qᵀ), and its λ_q per row, D_e per column and H_g
  // (grid_grams()).
  // λ_q and ν_q below include the mask m.
  void AddGridGram(int g);
  // Σ_j σ_j l_j of `row` at the current values (v null), or the same
  // combination of v's reduced columns, Σ_j σ_j v_j (without the mask).
  void RowCombination(const std::vector<BilinearGrid::Term>& row, int k,
                      Eigen::VectorXd* out,
                      const Eigen::VectorXd* v = nullptr) const;
  // Grid g's part of the two passes of ApplyReduced (BilinearGrid: residual
  // (q, e) = s_e D_e λ_q):
  // projected += J_pᵀ J_f v: τ_i s_e² D_e Mᵀ into each point i of column e,
  //   M = Σ_q λ_q ν_qᵀ;
  // out += J_fᵀ (J_f v − J_p y): σ_j M (H ν_q − N λ_q) into each weights
  //   block j of row q, N = Σ_e s_e² D_eᵀ Y_e, Y_e = Σ_i τ_i Y_i (y_i as
  //   3 × K).
  void AddGridProjected(int g, const Eigen::VectorXd& v,
                        Eigen::VectorXd* projected) const;
  void AddGridReduced(int g, const Eigen::VectorXd& v, const Eigen::VectorXd& y,
                      Eigen::VectorXd* out) const;

  const StructuredBlocks& blocks_;
  const StructuredJacobian& jacobian_;
  const int num_threads_;
  std::vector<Eigen::MatrixXd> gram_;  // J_pᵀ J_p per eliminated block
  std::vector<Eigen::LLT<Eigen::MatrixXd>> llt_;  // of C̃ per eliminated block

  // Only when residuals couple points (blocks.coupling_residuals):
  // per eliminated position k, the positions i > k coupled to it (sorted)
  // and the blocks J_iᵀ J_k (size_i × size_k) in the same order.
  std::vector<std::vector<int>> coupled_;
  std::vector<std::vector<Eigen::MatrixXd>> coupled_gram_;
  std::vector<int> position_;  // eliminated position per Block index
  // Per grid, at the current values: D_e per column, H_g, and the rows'
  // masked λ_q (K × Q, a column per row).
  std::vector<std::vector<Eigen::Matrix3Xd>> grid_difference_;
  std::vector<Eigen::MatrixXd> grid_lambdas_;
  std::vector<Eigen::MatrixXd> grid_gram_;
  SparseMatrix sparse_;  // lower triangle of C̃
  // Its Cholesky factor (CHOLMOD's, defined in the .cc so that only it
  // includes SuiteSparse's headers).
  class CoupledFactor;
  std::unique_ptr<CoupledFactor> coupled_factor_;
};

}  // namespace structured
}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_REFINE_SCHUR_ELIMINATION_H_
