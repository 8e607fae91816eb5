// The exact elimination of the point blocks from the Levenberg–Marquardt
// system (JᵀJ + μD) δ = −g (solvers/structured_solver.h), with J = [J_f J_p]
// split into the reduced (frame and shared) and eliminated (point) columns
// of solvers/structured_layout.h:
//   C̃ = J_pᵀ J_p + μ D_p, block-diagonal (no residual block holds two points),
//   S = J_fᵀ J_f + μ D_f − J_fᵀ J_p C̃⁻¹ J_pᵀ J_f (the Schur complement),
//   S δ_f = −g_f + J_fᵀ J_p C̃⁻¹ g_p,   δ_p = C̃⁻¹ (−g_p − J_pᵀ J_f δ_f).
// S is never formed: ApplyReduced() multiplies by it with two passes over
// the residual blocks in the order their Jacobians are stored.
//
// Assumes the StructuredJacobian holds the Jacobian of the current values;
// ComputeGram() after every Evaluate(true), Factor() for every μ. The same
// bits for any thread count (each point's blocks are its own; the sums are
// StructuredJacobian's).
#ifndef NRSFM_SOLVERS_SCHUR_ELIMINATION_H_
#define NRSFM_SOLVERS_SCHUR_ELIMINATION_H_

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <vector>

#include "solvers/structured_jacobian.h"
#include "solvers/structured_layout.h"

namespace nrsfm {
namespace structured {

class SchurElimination {
 public:
  // `blocks` and `jacobian` must outlive this.
  SchurElimination(const StructuredBlocks& blocks,
                   const StructuredJacobian& jacobian, int num_threads);

  // J_pᵀ J_p per eliminated block, from the current Jacobian.
  void ComputeGram();
  // Cholesky of C̃ = J_pᵀ J_p + μ D_p per eliminated block (d_eliminated: the
  // diagonal D_p, one value per eliminated column).
  void Factor(double mu, const Eigen::VectorXd& d_eliminated);
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
  const StructuredBlocks& blocks_;
  const StructuredJacobian& jacobian_;
  const int num_threads_;
  std::vector<Eigen::MatrixXd> gram_;  // J_pᵀ J_p per eliminated block
  std::vector<Eigen::LLT<Eigen::MatrixXd>> llt_;  // of C̃ per eliminated block
};

}  // namespace structured
}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_SCHUR_ELIMINATION_H_
