// The orthonormality residuals of frames for a corrective triple G
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
// One cost function holds the residuals of N frames (2N residuals), so that
// a solve over many frames has one residual block and a dense Jacobian.
// Block: G (3K × 3), column-major (entry i + 3K·j is G(i, j)). Hand-written
// Jacobian.
#ifndef NRSFM_PROBLEMS_ORTHONORMALITY_ERROR_H_
#define NRSFM_PROBLEMS_ORTHONORMALITY_ERROR_H_

#include <ceres/cost_function.h>
#include <glog/logging.h>

#include <Eigen/Core>
#include <utility>

namespace nrsfm {

class OrthonormalityError final : public ceres::CostFunction {
 public:
  // `rows`: 2N × 3K, the rows q₁, q₂ of N frames (N ≥ 1); 2N residuals.
  explicit OrthonormalityError(Eigen::MatrixXd rows) : rows_(std::move(rows)) {
    CHECK(rows_.rows() >= 2 && rows_.rows() % 2 == 0 && rows_.cols() >= 1);
    set_num_residuals(static_cast<int>(rows_.rows()));
    mutable_parameter_block_sizes()->push_back(3 *
                                               static_cast<int>(rows_.cols()));
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const Eigen::Index n = rows_.cols();
    const Eigen::Map<const Eigen::MatrixXd> g(parameters[0], n, 3);
    // rows a₁, a₂ per frame
    const Eigen::Matrix<double, Eigen::Dynamic, 3> a = rows_ * g;
    const bool with_jacobian = jacobians != nullptr && jacobians[0] != nullptr;
    for (Eigen::Index f = 0; f < rows_.rows() / 2; ++f) {
      const Eigen::RowVector3d a1 = a.row(2 * f), a2 = a.row(2 * f + 1);
      const double p = a1.squaredNorm();
      const double q = a2.squaredNorm();
      const double c = a1.dot(a2);
      const double norm = p + q;
      if (!(norm > 0.0)) return false;
      residuals[2 * f] = (p - q) / norm;
      residuals[2 * f + 1] = 2.0 * c / norm;
      if (!with_jacobian) continue;
      // d r / d G(i, j) = q₁ᵢ u₁ⱼ + q₂ᵢ u₂ⱼ with, for r₀ = (p − q) / (p + q),
      //   u₁ = 4 q a₁ / norm², u₂ = −4 p a₂ / norm²,
      // and for r₁ = 2c / (p + q),
      //   u₁ = 2 a₂ / norm − 4 c a₁ / norm², u₂ = 2 a₁ / norm − 4 c a₂ / norm².
      const double norm2 = norm * norm;
      const Eigen::RowVector3d u[2][2] = {
          {4.0 * q / norm2 * a1, -4.0 * p / norm2 * a2},
          {2.0 / norm * a2 - 4.0 * c / norm2 * a1,
           2.0 / norm * a1 - 4.0 * c / norm2 * a2}};
      for (int r = 0; r < 2; ++r) {
        // Row 2f + r of the row-major 2N × 3n Jacobian; column i + n·j is
        // entry (i, j) of the column-major G.
        double* row = jacobians[0] + (2 * f + r) * 3 * n;
        for (int j = 0; j < 3; ++j) {
          Eigen::Map<Eigen::RowVectorXd>(row + j * n, n) =
              u[r][0](j) * rows_.row(2 * f) + u[r][1](j) * rows_.row(2 * f + 1);
        }
      }
    }
    return true;
  }

  // Caller owns the results. One frame, or the frames of `rows` (2N × 3K).
  static ceres::CostFunction* Create(const Eigen::RowVectorXd& q1,
                                     const Eigen::RowVectorXd& q2) {
    Eigen::MatrixXd rows(2, q1.size());
    rows << q1, q2;
    return new OrthonormalityError(std::move(rows));
  }
  static ceres::CostFunction* Create(Eigen::MatrixXd rows) {
    return new OrthonormalityError(std::move(rows));
  }

 private:
  const Eigen::MatrixXd rows_;
};

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_ORTHONORMALITY_ERROR_H_
