// Preconditioned conjugate gradients for A x = b, A symmetric positive
// (semi-)definite and M⁻¹ ≈ A⁻¹ symmetric positive definite, both given as
// products, from x = 0. Stops when the recurrence's residual (not
// recomputed from A) has ||b − A x|| ≤ relative_tolerance · ||b||, after
// max_iterations, or when pᵀ A p is not positive (A singular along p, or
// NaN); x is then the last iterate. No allocation beyond a few vectors of
// b's size; the products decide the threads and the determinism.
#ifndef NRSFM_SOLVERS_REFINE_CONJUGATE_GRADIENTS_H_
#define NRSFM_SOLVERS_REFINE_CONJUGATE_GRADIENTS_H_

#include <Eigen/Core>
#include <functional>

namespace nrsfm {
namespace structured {

// out = A in, or out = M⁻¹ in.
using LinearOperator =
    std::function<void(const Eigen::VectorXd& in, Eigen::VectorXd* out)>;

struct ConjugateGradientsOptions {
  double relative_tolerance = 0.1;  // ||b − A x|| ≤ this · ||b||
  int max_iterations = 500;
};

// Returns the iterations done (products with A).
int ConjugateGradients(const ConjugateGradientsOptions& options,
                       const LinearOperator& apply_a,
                       const LinearOperator& apply_preconditioner,
                       const Eigen::VectorXd& b, Eigen::VectorXd* x);

}  // namespace structured
}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_REFINE_CONJUGATE_GRADIENTS_H_
