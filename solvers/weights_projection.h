// The basis weights' side of an LM step for the bilinear model (structured
// solver, solvers/structured_solver.h): every residual that holds a frame's
// basis weights l_t is linear in them once the other blocks are held — the
// reprojection residuals w (s Π R B_p l_t + T − x) and the terms of the form
// s · D λ (problems/jacobian_product.h, BilinearForm: the temporal shape
// prior, the Delaunay smoothness, the deformation prior). The Gauss-Newton
// model of the joint step leaves out the product of the weights' and the
// basis' steps, Σ_k δl_tk δb_pk; on the real sequences that product is
// all of the model's error in the long steps of a crawl (the rotations and
// the priors are linear along them; docs/performance.md, "The weights
// projected after every step"). So, after every trial step:
//
//  - Project(): the weights are set to their least-squares minimiser given
//    every other block (exact: the cost is quadratic in them). The normal
//    equations are one K × K block per frame, coupled with the next frame's
//    by terms that hold both (the temporal shape prior): a block-tridiagonal
//    system, factorised by block Cholesky.
//  - Balance(): when every term that holds weights or basis is unchanged by
//    their K × K mixing (l_t → A l_t, b_p → b_p A⁻¹, b_p read as 3 × K), A is
//    chosen so that Σ_t l_t l_tᵀ = Σ_p b_pᵀ b_p: the same cost, but neither
//    side's scale runs away from the other's, which the next step's
//    scaling D = diag(JᵀJ) and the radius would otherwise follow.
//
// Build() decides which of the two a problem allows; a problem that allows
// neither runs the plain LM step. Sums are formed per view and per group of
// residual blocks in a fixed order, so the results are the same bits for any
// thread count.
#ifndef NRSFM_SOLVERS_WEIGHTS_PROJECTION_H_
#define NRSFM_SOLVERS_WEIGHTS_PROJECTION_H_

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "solvers/reprojection_panel.h"
#include "solvers/structured_layout.h"

namespace nrsfm {
namespace structured {

class WeightsProjection {
 public:
  // The weights blocks are those of the panel's views and the weights blocks
  // of the BilinearForm residuals; the basis blocks are the eliminated ones.
  // Project() applies when every residual block that holds a free weights
  // block is the panel's or has a BilinearForm (no robust loss), and the
  // weights blocks held together by one residual are neighbours in block
  // order (the frames' chain). Balance() applies when, in addition, every
  // residual block that holds a basis block is the panel's or has a
  // BilinearForm without a mask, no such residual holds a constant weights or
  // basis block, no view of the panel has constant weights, and every
  // eliminated block has 3K values. `blocks` and `panel` (built) must outlive
  // this.
  void Build(const StructuredBlocks& blocks, const ReprojectionPanel& panel);

  bool projects() const { return projects_; }
  bool balances() const { return balances_; }
  int num_bases() const { return num_bases_; }

  // Sets the free weights blocks to the minimiser of the cost over them (the
  // other blocks held) from `residuals` (rows of solvers/structured_layout.h)
  // at the blocks' current values. False, with nothing changed, when it does
  // not apply or the normal equations are not positive definite or the
  // result is not finite.
  bool Project(const Eigen::VectorXd& residuals, int num_threads) const;

  // Mixes weights and basis so that Σ_t l_t l_tᵀ = Σ_p b_pᵀ b_p (A = P½,
  // P the geometric mean G_w⁻¹ # G_b: P G_w P = G_b), and returns the A
  // applied in `applied` (may be null). False, with nothing changed, when it
  // does not apply or a Gram is singular.
  bool Balance(Eigen::MatrixXd* applied) const;
  // l_t → A l_t for every weights block and b_p → b_p A⁻¹ for every basis
  // block (A K × K, invertible): the cost is unchanged where Balance()
  // applies.
  void Mix(const Eigen::MatrixXd& a) const;

 private:
  // A residual block with a BilinearForm as Project() reads it: σ summed
  // per weights block of its group (lo, hi), s, its basis slots with τ
  // (basis_slots_[first_basis …]) and its mask (masks_, −1 = none).
  struct Term {
    int residual = 0;
    double sigma[2] = {0.0, 0.0};
    double scale = 0.0;
    int first_basis = 0, num_basis = 0;
    int mask = -1;
  };
  // The terms that hold weights blocks lo and hi (indices into weights_,
  // hi = lo or lo + 1), in storage order.
  struct Group {
    int lo = 0, hi = 0;
    std::vector<Term> terms;
  };

  const StructuredBlocks* blocks_ = nullptr;
  const ReprojectionPanel* panel_ = nullptr;
  int num_bases_ = 0;
  bool projects_ = false, balances_ = false;
  std::vector<int> weights_;     // Block indices, increasing
  std::vector<int> index_of_;    // per Block: index into weights_, −1 = none
  std::vector<int> view_index_;  // per view of the panel, −1 = constant
  std::vector<Group> groups_;    // sorted by (lo, hi)
  std::vector<std::pair<int, double>> basis_slots_;  // (slot, τ)
  std::vector<std::vector<double>> masks_;
};

}  // namespace structured
}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_WEIGHTS_PROJECTION_H_
