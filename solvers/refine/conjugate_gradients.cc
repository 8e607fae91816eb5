#include "solvers/refine/conjugate_gradients.h"

namespace nrsfm {
namespace structured {

int ConjugateGradients(const ConjugateGradientsOptions& options,
                       const LinearOperator& apply_a,
                       const LinearOperator& apply_preconditioner,
                       const Eigen::VectorXd& b, Eigen::VectorXd* solution) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size()), residual = b, z, p, q;
  apply_preconditioner(residual, &z);
  p = z;
  double rz = residual.dot(z);
  const double target = options.relative_tolerance * b.norm();
  int iterations = 0;
  while (iterations < options.max_iterations && residual.norm() > target) {
    apply_a(p, &q);
    const double pq = p.dot(q);
    if (!(pq > 0.0)) break;
    const double alpha = rz / pq;
    x += alpha * p;
    residual -= alpha * q;
    apply_preconditioner(residual, &z);
    const double rz_next = residual.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
    ++iterations;
  }
  *solution = x;
  return iterations;
}

}  // namespace structured
}  // namespace nrsfm
