// The orthonormality residual of one frame for a corrective triple G
// (Akhter, Sheikh and Khan 2009; docs/factorization.md, "The corrective
// triple"). With q₁, q₂ the frame's two rows of the rank-3K motion factor Q̂
// (1 × 3K each) and G a 3K × 3 column triple, a₁ = q₁ G and a₂ = q₂ G must be
// the rows of c Π R for some scale c: equal norms and orthogonal. The
// residual is scale-free,
//
//   r = ( |a₁|² − |a₂|²,  2 a₁·a₂ ) / (|a₁|² + |a₂|²),   2 residuals,
//
// each in [−1, 1], 0 for an exact scaled rotation, invariant to G ← α G U
// (scale, rotation, reflection: the global gauges). Undefined (Evaluate
// returns false) when a₁ = a₂ = 0.
//
// Block: G (3K), column-major (entry i + 3K·j is G(i, j)). Hand-written
// Jacobian.
#ifndef NRSFM_PROBLEMS_ORTHONORMALITY_ERROR_H_
#define NRSFM_PROBLEMS_ORTHONORMALITY_ERROR_H_

#include <ceres/cost_function.h>
#include <Eigen/Core>

namespace nrsfm {

class OrthonormalityError final : public ceres::CostFunction {
 public:
  // `q1`, `q2`: the frame's rows of Q̂ (1 × 3K each).
  OrthonormalityError(const Eigen::RowVectorXd& q1, const Eigen::RowVectorXd& q2)
      : q1_(q1), q2_(q2) {
    set_num_residuals(2);
    mutable_parameter_block_sizes()->push_back(3 * static_cast<int>(q1.size()));
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int n = static_cast<int>(q1_.size());
    const Eigen::Map<const Eigen::MatrixXd> g(parameters[0], n, 3);
    const Eigen::RowVector3d a1 = q1_ * g;
    const Eigen::RowVector3d a2 = q2_ * g;
    const double p = a1.squaredNorm();
    const double q = a2.squaredNorm();
    const double c = a1.dot(a2);
    const double norm = p + q;
    if (!(norm > 0.0)) return false;
    residuals[0] = (p - q) / norm;
    residuals[1] = 2.0 * c / norm;
    if (jacobians == nullptr || jacobians[0] == nullptr) return true;
    // d/dG (n × 3, column-major like the block) of p, q, c.
    const Eigen::MatrixXd dp = 2.0 * q1_.transpose() * a1;
    const Eigen::MatrixXd dq = 2.0 * q2_.transpose() * a2;
    const Eigen::MatrixXd dc = q1_.transpose() * a2 + q2_.transpose() * a1;
    const Eigen::MatrixXd dnorm = dp + dq;
    const Eigen::MatrixXd d0 = (dp - dq) / norm - (p - q) / (norm * norm) * dnorm;
    const Eigen::MatrixXd d1 = 2.0 * dc / norm - 2.0 * c / (norm * norm) * dnorm;
    // Row-major 2 × 3n Jacobian; column j of it is entry j of the
    // column-major G.
    Eigen::Map<Eigen::Matrix<double, 2, Eigen::Dynamic, Eigen::RowMajor>> j(
        jacobians[0], 2, 3 * n);
    j.row(0) = Eigen::Map<const Eigen::RowVectorXd>(d0.data(), 3 * n);
    j.row(1) = Eigen::Map<const Eigen::RowVectorXd>(d1.data(), 3 * n);
    return true;
  }

  // Caller owns the result.
  static ceres::CostFunction* Create(const Eigen::RowVectorXd& q1,
                                     const Eigen::RowVectorXd& q2) {
    return new OrthonormalityError(q1, q2);
  }

 private:
  const Eigen::RowVectorXd q1_;
  const Eigen::RowVectorXd q2_;
};

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_ORTHONORMALITY_ERROR_H_
