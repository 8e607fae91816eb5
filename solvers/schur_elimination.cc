#include "solvers/schur_elimination.h"

#include <algorithm>

#include "core/parallel_for.h"

namespace nrsfm {
namespace structured {
namespace {

// Loops over the eliminated blocks (points) are split in pieces of this many
// (a point holds the residuals of every frame).
constexpr int kEliminatedGrain = 1;

}  // namespace

SchurElimination::SchurElimination(const StructuredBlocks& blocks,
                                   const StructuredJacobian& jacobian,
                                   int num_threads)
    : blocks_(blocks), jacobian_(jacobian), num_threads_(num_threads) {}

void SchurElimination::ComputeGram() {
  gram_.resize(blocks_.eliminated_blocks.size());
  ParallelFor(
      static_cast<int>(blocks_.eliminated_blocks.size()), num_threads_,
      kEliminatedGrain, [&](int begin, int end) {
        RowMatrix stacked;
        for (int k = begin; k < end; ++k) {
          const Block& b = blocks_.blocks[blocks_.eliminated_blocks[k]];
          // Residuals with a basis factor add (l lᵀ) ⊗ (Aᵀ A)
          // directly (lower triangle).
          Eigen::MatrixXd& c = gram_[k];
          c.setZero(b.size, b.size);
          int rows = 0;
          for (const Ref& ref : blocks_.eliminated_refs[k]) {
            const Residual& r = blocks_.residuals[ref.residual];
            if (r.gram) {
              const int slot = r.EliminatedSlot();
              r.product->AddGram(r.parameters.data(), slot, slot, c.data(),
                                 static_cast<int>(c.rows()));
              continue;
            }
            if (r.basis_factor == nullptr) {
              rows += r.m;
              continue;
            }
            const double* a = jacobian_.Factor(r);
            double ata[9];
            for (int i = 0; i < 3; ++i) {
              for (int j = 0; j < 3; ++j) {
                ata[3 * i + j] = a[i] * a[j] + a[3 + i] * a[3 + j];
              }
            }
            for (int kb = 0; kb < r.num_bases; ++kb) {
              for (int ka = kb; ka < r.num_bases; ++ka) {
                const double ll = r.weights[ka] * r.weights[kb];
                for (int j = 0; j < 3; ++j) {
                  for (int i = (ka == kb ? j : 0); i < 3; ++i) {
                    c(3 * ka + i, 3 * kb + j) += ll * ata[3 * i + j];
                  }
                }
              }
            }
          }
          if (rows > 0) {
            // The block's stored Jacobian rows stacked, then one
            // symmetric rank update (the small products one by one
            // cost more).
            stacked.resize(rows, b.size);
            rows = 0;
            for (const Ref& ref : blocks_.eliminated_refs[k]) {
              const Residual& r = blocks_.residuals[ref.residual];
              if (r.basis_factor != nullptr || r.gram) continue;
              stacked.middleRows(rows, r.m) =
                  jacobian_.Cols(r, r.eliminated_jcol, b.size);
              rows += r.m;
            }
            c.selfadjointView<Eigen::Lower>().rankUpdate(stacked.transpose());
          }
          c.triangularView<Eigen::StrictlyUpper>() = c.transpose();
        }
      });
}

void SchurElimination::Factor(double mu, const Eigen::VectorXd& d_eliminated) {
  llt_.resize(blocks_.eliminated_blocks.size());
  ParallelFor(static_cast<int>(blocks_.eliminated_blocks.size()), num_threads_,
              kEliminatedGrain, [&](int begin, int end) {
                for (int k = begin; k < end; ++k) {
                  const Block& b = blocks_.blocks[blocks_.eliminated_blocks[k]];
                  Eigen::MatrixXd c = gram_[k];
                  c.diagonal() += mu * d_eliminated.segment(b.offset, b.size);
                  llt_[k].compute(c);
                }
              });
}

void SchurElimination::SolveEliminated(const Eigen::VectorXd& in,
                                       Eigen::VectorXd* out) const {
  out->resize(blocks_.num_eliminated);
  for (std::size_t k = 0; k < blocks_.eliminated_blocks.size(); ++k) {
    const Block& b = blocks_.blocks[blocks_.eliminated_blocks[k]];
    out->segment(b.offset, b.size) =
        llt_[k].solve(in.segment(b.offset, b.size));
  }
}

void SchurElimination::ApplyReduced(const Eigen::VectorXd& v, double mu,
                                    const Eigen::VectorXd& d_reduced,
                                    Eigen::VectorXd* out) const {
  // S v = J_fᵀ (J_f v − J_p C̃⁻¹ J_pᵀ J_f v) + μ D_f v, in two passes over the
  // residual blocks in the order their Jacobians are stored (they do not fit
  // in the caches, so reading them is the cost): rows = J_f v and J_pᵀ rows;
  // then J_fᵀ (rows − J_p C̃⁻¹ J_pᵀ rows).
  Eigen::VectorXd rows(blocks_.num_rows), projected, solved;
  jacobian_.MultiplyJReducedAndJtEliminated(v, &rows, &projected);
  SolveEliminated(projected, &solved);
  jacobian_.SubtractJEliminatedAndMultiplyJtReduced(solved, &rows, out);
  out->array() += mu * d_reduced.array() * v.array();
}

void SchurElimination::ReducedRightHandSide(
    const Eigen::VectorXd& gradient_reduced,
    const Eigen::VectorXd& gradient_eliminated, Eigen::VectorXd* rhs) const {
  Eigen::VectorXd solved, rows;
  SolveEliminated(gradient_eliminated, &solved);
  jacobian_.MultiplyJ(nullptr, &solved, &rows);
  jacobian_.MultiplyJtReduced(rows, rhs);
  *rhs -= gradient_reduced;
}

void SchurElimination::BackSubstitute(
    const Eigen::VectorXd& step_reduced,
    const Eigen::VectorXd& gradient_eliminated,
    Eigen::VectorXd* step_eliminated) const {
  Eigen::VectorXd jx, projected;
  jacobian_.MultiplyJ(&step_reduced, nullptr, &jx);
  jacobian_.MultiplyJtEliminated(jx, &projected);
  SolveEliminated(-gradient_eliminated - projected, step_eliminated);
}

}  // namespace structured
}  // namespace nrsfm
