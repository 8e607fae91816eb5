// The residuals and the Jacobian of the problem laid out as
// solvers/refine/structured_layout.h says, and the products with the Jacobian.
//
// Evaluate() stores r and J at the blocks' current values; for a residual
// block with a robust loss both are corrected as Ceres does (Triggs et al.),
// so that JᵀJ and Jᵀr are the loss's Gauss–Newton model, while the cost is
// ½ Σ ρ(||r_i||²) of the uncorrected residuals. J is in tangent space (the
// ambient Jacobian times the manifold's PlusJacobian). Not stored: the
// columns of a reprojection residual's basis block (only its 2 × 3 factor
// A, Residual::basis_factor), every column of a residual that provides
// its Gram blocks (Residual::gram) and every column of a residual that the
// panel holds (uses_panel(): the panel forms its products and Gram blocks
// from the blocks' values). Products with a residual that provides them
// (Residual::product) are formed from its parameters, so products and
// sums read the blocks' values: these must be those of the last
// Evaluate(true).
//
// Determinism: sums over residual blocks are added in kReductionPieces
// pieces fixed by the problem (core/math/parallel_for.h, ParallelForPieces),
// and every other loop writes only its own rows, so the results are the same
// bits for any thread count.
#ifndef NRSFM_SOLVERS_REFINE_STRUCTURED_JACOBIAN_H_
#define NRSFM_SOLVERS_REFINE_STRUCTURED_JACOBIAN_H_

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "core/math/parallel_for.h"
#include "solvers/refine/reprojection_panel.h"
#include "solvers/refine/structured_layout.h"

namespace nrsfm {
namespace structured {

using ConstRowMap = Eigen::Map<const RowMatrix, 0, Eigen::OuterStride<>>;

// Loops are split over threads in pieces of at least this many items
// (core/math/parallel_for.h): residual blocks are cheap.
constexpr int kGrain = 64;
// Sums over residuals (the cost, Jᵀr and Jᵀ products) are added in this many
// fixed pieces, whatever the thread count, so that the result does not
// depend on it (core/math/parallel_for.h); at most this many threads share
// them.
constexpr int kReductionPieces = 16;

class StructuredJacobian {
 public:
  // `blocks` must outlive this. With allow_panel the reprojection residuals
  // are one panel when it pays (ReprojectionPanel::Build()); without, every
  // residual block is taken one by one (a reference for tests).
  StructuredJacobian(const StructuredBlocks& blocks, int num_threads,
                     bool allow_panel = true);

  // r (and J when with_jacobian) at the blocks' current values; *cost =
  // ½ Σ ρ(||r_i||²). False when a cost function fails or the cost is not
  // finite (r and J are then partly written).
  bool Evaluate(bool with_jacobian, double* cost);
  const Eigen::VectorXd& residuals() const { return r_; }

  // y (r.m values) += J_r x for the reduced and eliminated parts given
  // (null = zero), and the transposed products into the parts wanted; `r`
  // not held by the panel.
  void AddResidualJx(const Residual& r, const double* reduced,
                     const double* eliminated, double* y) const;
  void AddResidualJty(const Residual& r, const double* y, double* reduced,
                      double* eliminated) const;
  // *out (size values) = Σ_i body(i, sum) over the residual blocks in storage
  // order (only those of `only` when given), the pieces' sums added in piece
  // order.
  template <typename Body>
  void SumOverResiduals(int size, const Body& body, Eigen::VectorXd* out,
                        const std::vector<int>* only = nullptr) const;
  // rows = J [reduced; eliminated] (null = zero), residual by residual: not
  // on a Jacobian that uses_panel() (a programmer error).
  void MultiplyJ(const Eigen::VectorXd* reduced,
                 const Eigen::VectorXd* eliminated,
                 Eigen::VectorXd* rows) const;
  // Jᵀ r at the last Evaluate(true): its reduced and eliminated columns (the
  // reprojection residuals as one panel when uses_panel()).
  void Gradient(Eigen::VectorXd* reduced, Eigen::VectorXd* eliminated) const;
  // (J δ)·r and ||J δ||² for δ = [reduced; eliminated], r at the last
  // Evaluate(true) (the linear model's decrease).
  void StepProducts(const Eigen::VectorXd& reduced,
                    const Eigen::VectorXd& eliminated, double* dot,
                    double* squared) const;
  // out = J_fᵀ rows, J_pᵀ rows (residual by residual, as MultiplyJ()).
  void MultiplyJtReduced(const Eigen::VectorXd& rows,
                         Eigen::VectorXd* out) const;
  void MultiplyJtEliminated(const Eigen::VectorXd& rows,
                            Eigen::VectorXd* out) const;
  // The two passes of a product with the Schur complement
  // (solvers/refine/schur_elimination.h), each one pass over the residual
  // blocks in storage order: rows = J_f reduced and projected = J_pᵀ rows; then
  // rows −= J_p eliminated and out = J_fᵀ rows (rows null: out =
  // J_fᵀ (−J_p eliminated), without a first pass). When uses_panel() the
  // reprojection residuals are one panel, whose J_f reduced the first pass
  // keeps inside the panel (their entries of `rows` are left unset): a
  // second pass with rows must follow its first pass. Both leave out the
  // residuals of the grids (Residual::in_grid), whose part SchurElimination
  // adds.
  void MultiplyJReducedAndJtEliminated(const Eigen::VectorXd& reduced,
                                       Eigen::VectorXd* rows,
                                       Eigen::VectorXd* projected) const;
  void SubtractJEliminatedAndMultiplyJtReduced(
      const Eigen::VectorXd& eliminated, Eigen::VectorXd* rows,
      Eigen::VectorXd* out) const;
  // Whether the two passes above take the reprojection residuals as one
  // panel (solvers/refine/reprojection_panel.h).
  bool uses_panel() const { return use_panel_; }
  // The panel when the passes use it (its Gram blocks with it), else null.
  const ReprojectionPanel* panel() const {
    return use_panel_ ? &panel_ : nullptr;
  }

  // diag(JᵀJ), the columns' sums of squares, unclamped, without the grids'
  // residuals (SchurElimination::AddGridColumnSquaredNorms adds their part).
  void ColumnSquaredNorms(Eigen::VectorXd* reduced,
                          Eigen::VectorXd* eliminated) const;

  // The stored Jacobian of `r` (not for a residual the panel holds, one in
  // a grid or one with Residual::gram), and its columns [jcol, jcol + width).
  const double* J(const Residual& r) const {
    return jacobian_.data() + stored_[&r - blocks_.residuals.data()];
  }
  ConstRowMap Cols(const Residual& r, int jcol, int width) const {
    return ConstRowMap(J(r) + jcol, r.m, width, Eigen::OuterStride<>(r.width));
  }
  // The 2 × 3 factor A (row-major) of a residual with a basis_factor that
  // the panel does not hold, stored after its Jacobian.
  const double* Factor(const Residual& r) const {
    return J(r) + static_cast<std::size_t>(r.m) * r.width;
  }

 private:
  // Whether residual i's Jacobian is stored (see jacobian_).
  bool Stores(int i) const;
  double* MutableJ(const Residual& r) {
    return jacobian_.data() + stored_[&r - blocks_.residuals.data()];
  }
  // rotations_ (and plus_jacobians_ when with_jacobian) at the blocks'
  // current values.
  void FormSharedDerivatives(bool with_jacobian);
  // The residuals of the two Schur-complement passes one by one: those in
  // no grid and not in the panel, or null (all).
  const std::vector<int>* PassResiduals() const {
    if (use_panel_) return &pass_residuals_;
    return blocks_.grids.empty() ? nullptr : &blocks_.not_in_grid;
  }

  const StructuredBlocks& blocks_;
  const int num_threads_;
  // The stored Jacobians (each followed by its factor A when it has one),
  // residual i's from stored_[i]; nothing for a residual with Residual::gram,
  // one in a grid (Residual::in_grid) or one the panel holds.
  std::vector<double> jacobian_;
  std::vector<std::size_t> stored_;
  Eigen::VectorXd r_;
  // Formed once per Evaluate() for every residual block that shares them,
  // indexed by Block: the PlusJacobian of each block with a manifold, and the
  // ProjectedRotation of each rotation block of a reprojection residual
  // (is_rotation_); unused entries stay empty.
  std::vector<RowMatrix> plus_jacobians_;
  std::vector<ProjectedRotation> rotations_;
  std::vector<char> is_rotation_;
  // The reprojection residuals as one panel when it pays
  // (solvers/refine/reprojection_panel.h, Build()), and the residuals the
  // passes then take one by one.
  ReprojectionPanel panel_;
  bool use_panel_ = false;
  std::vector<int> pass_residuals_;
  std::vector<int> non_panel_;  // the residuals the panel does not hold
};

template <typename Body>
void StructuredJacobian::SumOverResiduals(int size, const Body& body,
                                          Eigen::VectorXd* out,
                                          const std::vector<int>* only) const {
  std::vector<Eigen::VectorXd> sums(kReductionPieces);
  const int n = static_cast<int>(only != nullptr ? only->size()
                                                 : blocks_.residuals.size());
  const int pieces =
      ParallelForPieces(n, kReductionPieces, num_threads_, kGrain,
                        [&](int begin, int end, int piece) {
                          Eigen::VectorXd& sum = sums[piece];
                          sum.setZero(size);
                          for (int i = begin; i < end; ++i)
                            body(only != nullptr ? (*only)[i] : i, sum.data());
                        });
  *out = std::move(sums[0]);
  for (int w = 1; w < pieces; ++w) {
    if (sums[w].size() == size) *out += sums[w];
  }
}

}  // namespace structured
}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_REFINE_STRUCTURED_JACOBIAN_H_
