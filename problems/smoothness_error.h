// Delaunay-neighbour smoothness of the frames' shapes (the `smoothness` extra
// term, docs/problem.md; after Torresani et al. 2001's shape
// regularisation), one residual block per frame t and neighbour edge (i, j)
// (problems/delaunay_edges.h):
//
//   r = sqrt(λ / F) · α_ij · (S_t[:, i] − S_t[:, j])
//     = sqrt(λ / F) · α_ij · Σ_k l_tk (b_i,k − b_j,k),   3 residuals,
//
// l_t the frame's K weights, b_p = [S_1[:,p]; …; S_K[:,p]] the basis column
// of point p (Model::basis, input units), α_ij the edge weight
// (dimensionless, ~1 for a typical edge), F the number of frames, λ ≥ 0 the
// term's weight (dimensionless: λ = 1 weighs a neighbour difference of the
// shape, averaged over the frames, like a reprojection error of the same
// size). The cost ½ (λ / F) α² Σ_t ||S_t[:, i] − S_t[:, j]||² pulls a point
// towards its neighbours in every frame's shape, so a point that the images
// leave ambiguous (few observations) takes its neighbours' depth.
//
// Gauge: the term reads only the shapes, so it is invariant to the K × K
// gauge of the model (basis Q B, weights L Q⁻¹ give the same shapes). The
// earlier form √λ α (b_i − b_j) on the basis alone (the same cost in the
// gauge where (1/F) Σ_t l_t l_tᵀ = I) was not: it lowered its cost by
// shrinking the basis while the weights grew, without changing any shape,
// so a refinement never ended by its tolerance (docs/performance.md).
//
// Blocks: l_t (K), b_i (3K), b_j (3K). Hand-written Jacobian:
//   ∂r/∂l_tk = s (b_i,k − b_j,k),  ∂r/∂b_i,k = s l_tk I₃ = −∂r/∂b_j,k,
// s = sqrt(λ / F) α_ij.
#ifndef NRSFM_PROBLEMS_SMOOTHNESS_ERROR_H_
#define NRSFM_PROBLEMS_SMOOTHNESS_ERROR_H_

#include <ceres/cost_function.h>
#include <glog/logging.h>

#include "problems/jacobian_product.h"

namespace nrsfm {

class SmoothnessError final : public ceres::CostFunction,
                              public JacobianProduct {
 public:
  // `scale` = sqrt(λ / F) · α_ij.
  SmoothnessError(int num_bases, double scale)
      : num_bases_(num_bases), scale_(scale) {
    CHECK_GE(num_bases, 1);
    set_num_residuals(3);
    mutable_parameter_block_sizes()->push_back(num_bases);
    mutable_parameter_block_sizes()->push_back(3 * num_bases);
    mutable_parameter_block_sizes()->push_back(3 * num_bases);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* l = parameters[0];
    const double* b_i = parameters[1];
    const double* b_j = parameters[2];
    const int k3 = 3 * num_bases_;
    residuals[0] = residuals[1] = residuals[2] = 0.0;
    for (int k = 0; k < num_bases_; ++k) {
      for (int c = 0; c < 3; ++c) {
        residuals[c] += l[k] * (b_i[3 * k + c] - b_j[3 * k + c]);
      }
    }
    for (int c = 0; c < 3; ++c) residuals[c] *= scale_;
    if (jacobians == nullptr) return true;
    if (jacobians[0] != nullptr) {  // 3 × K, row-major
      for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < num_bases_; ++k) {
          jacobians[0][c * num_bases_ + k] =
              scale_ * (b_i[3 * k + c] - b_j[3 * k + c]);
        }
      }
    }
    for (int slot = 1; slot <= 2; ++slot) {
      if (jacobians[slot] == nullptr) continue;
      const double sign = slot == 1 ? scale_ : -scale_;
      double* j = jacobians[slot];  // 3 × 3K, row-major
      for (int i = 0; i < 3 * k3; ++i) j[i] = 0.0;
      for (int k = 0; k < num_bases_; ++k) {
        for (int c = 0; c < 3; ++c) j[c * k3 + 3 * k + c] = sign * l[k];
      }
    }
    return true;
  }

  // The products from the parameters (problems/jacobian_product.h): the
  // stored Jacobian would be read 3 × 7K values at a time, F times per edge.
  void AddJacobianProduct(double const* const* parameters,
                          double const* const* x, double* y) const override {
    const double* l = parameters[0];
    const double* b_i = parameters[1];
    const double* b_j = parameters[2];
    double sum[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < num_bases_; ++k) {
      for (int c = 0; c < 3; ++c) {
        const int e = 3 * k + c;
        double v = 0.0;
        if (x[0] != nullptr) v += (b_i[e] - b_j[e]) * x[0][k];
        if (x[1] != nullptr) v += l[k] * x[1][e];
        if (x[2] != nullptr) v -= l[k] * x[2][e];
        sum[c] += v;
      }
    }
    for (int c = 0; c < 3; ++c) y[c] += scale_ * sum[c];
  }

  void AddJacobianTransposeProduct(double const* const* parameters,
                                   const double* y,
                                   double* const* x) const override {
    const double* l = parameters[0];
    const double* b_i = parameters[1];
    const double* b_j = parameters[2];
    const double sy[3] = {scale_ * y[0], scale_ * y[1], scale_ * y[2]};
    for (int k = 0; k < num_bases_; ++k) {
      if (x[0] != nullptr) {
        double v = 0.0;
        for (int c = 0; c < 3; ++c)
          v += (b_i[3 * k + c] - b_j[3 * k + c]) * sy[c];
        x[0][k] += v;
      }
      for (int c = 0; c < 3; ++c) {
        if (x[1] != nullptr) x[1][3 * k + c] += l[k] * sy[c];
        if (x[2] != nullptr) x[2][3 * k + c] -= l[k] * sy[c];
      }
    }
  }

  // r = s · (B_i − B_j) l_t.
  bool GetBilinearForm(BilinearForm* form) const override {
    *form = BilinearForm{
        scale_, num_bases_, {1.0, 1.0, -1.0}, {true, false, false}, {}};
    return true;
  }

  int num_bases() const { return num_bases_; }
  double scale() const { return scale_; }

  // `sqrt_weight` = sqrt(λ / F). Caller owns the result.
  static ceres::CostFunction* Create(int num_bases, double sqrt_weight,
                                     double alpha) {
    return new SmoothnessError(num_bases, sqrt_weight * alpha);
  }

 private:
  int num_bases_;
  double scale_;
};

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_SMOOTHNESS_ERROR_H_
