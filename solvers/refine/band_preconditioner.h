// The preconditioner of the structured solver's conjugate gradients
// (solvers/refine/structured_solver.h): the reduced columns' part of JᵀJ + μD
// (solvers/refine/structured_layout.h: frame groups, then shared blocks), as
//   M = [A B; Bᵀ C],
// A: every coupling between frame groups up to StructuredBlocks::band apart
// (what the temporal terms make), factorised as a block band, L Lᵀ;
// B: frame groups × shared blocks (the dense border); C: shared × shared.
// M⁻¹ is applied through the Schur complement of A, C − Bᵀ A⁻¹ B. The
// coupling between frames through shared points (what the elimination of
// the points adds, solvers/refine/schur_elimination.h) is not in M: it is left
// to the conjugate gradients. The panel's residuals
// (solvers/refine/reprojection_panel.h) are added as their views' Grams.
//
// A diagonal block of the band that is not positive definite gets a
// diagonal shift of 1e-10 × its largest diagonal entry (a preconditioner
// only needs to be positive definite). Assumes the StructuredJacobian holds
// the Jacobian of the current values; Build() for every μ. The same bits for
// any thread count (each frame group's blocks are its own).
#ifndef NRSFM_SOLVERS_REFINE_BAND_PRECONDITIONER_H_
#define NRSFM_SOLVERS_REFINE_BAND_PRECONDITIONER_H_

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <utility>
#include <vector>

#include "solvers/refine/structured_jacobian.h"
#include "solvers/refine/structured_layout.h"

namespace nrsfm {
namespace structured {

class BandPreconditioner {
 public:
  // `blocks` and `jacobian` must outlive this.
  BandPreconditioner(const StructuredBlocks& blocks,
                     const StructuredJacobian& jacobian, int num_threads);

  // Forms and factorises M for JᵀJ + μ diag(d_reduced) (one value per
  // reduced column). The grids' residuals (StructuredBlocks::grids) are not
  // read: their part is σ_a σ_b grid_grams[g] between the weights blocks a,
  // b of each row of grid g (SchurElimination::grid_grams()).
  void Build(double mu, const Eigen::VectorXd& d_reduced,
             const std::vector<Eigen::MatrixXd>& grid_grams);
  // out = M⁻¹ in (reduced columns).
  void Apply(const Eigen::VectorXd& in, Eigen::VectorXd* out) const;

 private:
  // The Gram blocks of a residual that provides them (Residual::gram) for its
  // slots in segment `a` (of group g) against every reduced slot of a group
  // ≤ g (the band's lower triangle) or shared (the border).
  void AddGram(const Residual& r, const Segment& a, int g);
  // The panel's Gram of view `view` (ReprojectionPanel::ViewGram()): its
  // rows of group g against every group ≤ g (the band's lower triangle) and
  // the shared blocks (the border), or for g = −1 its shared rows against
  // the shared blocks (the corner).
  void AddViewGram(int view, int g);
  // Solves L Lᵀ x = x in place with the band factor (x: a vector or a
  // matrix of right-hand sides).
  template <typename Matrix>
  void BandSolve(Matrix* x) const;

  const StructuredBlocks& blocks_;
  const StructuredJacobian& jacobian_;
  const int num_threads_;
  // Per group, the (grid, row) pairs with a weights block in it.
  std::vector<std::vector<std::pair<int, int>>> grid_rows_;
  // Per group, the panel's views with a block in it, and those with a
  // shared block (none without a panel).
  std::vector<std::vector<int>> panel_views_;
  std::vector<int> shared_panel_views_;
  Eigen::MatrixXd corner_;                          // C, while Build() forms it
  std::vector<std::vector<Eigen::MatrixXd>> band_;  // [g][d]: block (g, g − d)
  Eigen::MatrixXd border_, border_solved_;          // B, A⁻¹ B
  Eigen::LLT<Eigen::MatrixXd> corner_llt_;          // of C − Bᵀ A⁻¹ B
};

}  // namespace structured
}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_REFINE_BAND_PRECONDITIONER_H_
