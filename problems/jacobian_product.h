// Products with a residual block's Jacobian computed from its parameters,
// for a solver that multiplies by the Jacobian many times per step
// (solvers/refine/structured_solver.h: every conjugate-gradient iteration).
//
// A stored Jacobian is read from memory at every product; a cost function
// whose Jacobian is structured (repeated or mostly zero entries) can form
// the same products from its parameters with far less memory traffic. The
// temporal shape prior is one: its Jacobian is 3 × 5K per frame pair and
// point, of which 3K entries hold the point's basis (shared by every frame)
// and 3K the frame's weight change (problems/temporal_error.h).
#ifndef NRSFM_PROBLEMS_JACOBIAN_PRODUCT_H_
#define NRSFM_PROBLEMS_JACOBIAN_PRODUCT_H_

#include <vector>

namespace nrsfm {

// The form r = s · D λ of a residual block of 3 residuals (no robust loss),
// λ = m ⊙ Σ_j σ_j l_j over its weights blocks l_j (K values each; m a fixed
// mask of K values, all 1 unless `mask` says otherwise) and
// D = Σ_i τ_i B_i (3 × K) over its basis blocks b_i (3K values each, read as
// 3 × K: column k is the point's column of basis shape k, Model::basis), s a
// scale. The Delaunay smoothness of a frame's shape (l_t; b_i − Σ_j w_ij b_j),
// the temporal shape prior (l_t − l_(t−1); b_p) and the deformation prior (m ⊙
// l_t with m = (0, 1, …, 1); b_p) have it. A solver can then sum such blocks of
// one term over all frames at once (solvers/refine/structured_layout.h,
// BilinearGrid).
struct BilinearForm {
  double scale = 0.0;            // s
  int num_bases = 0;             // K
  std::vector<double> signs;     // σ_j or τ_i, per parameter block in order
  std::vector<bool> is_weights;  // per parameter block: l_j (true) or b_i
  std::vector<double> mask;      // m (K values), or empty: all 1
};

// For a residual block whose parameter blocks have no manifold (the tangent
// is the ambient space) and no robust loss. Both products are with the
// Jacobian at `parameters`, exactly the one Evaluate() gives there.
class JacobianProduct {
 public:
  virtual ~JacobianProduct() = default;

  // y (num_residuals) += Σ_b J_b x[b]; a null x[b] is zero.
  virtual void AddJacobianProduct(double const* const* parameters,
                                  double const* const* x, double* y) const = 0;

  // x[b] += J_bᵀ y for every b whose x[b] is not null.
  virtual void AddJacobianTransposeProduct(double const* const* parameters,
                                           const double* y,
                                           double* const* x) const = 0;

  // Optional: whether AddGram is provided. Then a solver needs no stored
  // Jacobian for the block at all (its products, Gram blocks and diagonal
  // come from these calls).
  virtual bool ProvidesGram() const { return false; }
  // out += J_aᵀ J_b for parameter blocks a and b (size_a × size_b,
  // column-major with leading dimension ld). Only called when ProvidesGram().
  virtual void AddGram(double const* const* /*parameters*/, int /*a*/,
                       int /*b*/, double* /*out*/, int /*ld*/) const {}
  // out (size_a) += diag(J_aᵀ J_a), the squared norms of block a's columns.
  // Only called when ProvidesGram().
  virtual void AddGramDiagonal(double const* const* /*parameters*/, int /*a*/,
                               double* /*out*/) const {}
  // Optional: whether the block has the form above; then `form` describes
  // it. The products above must agree with it.
  virtual bool GetBilinearForm(BilinearForm* /*form*/) const { return false; }
};

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_JACOBIAN_PRODUCT_H_
