// Delaunay-neighbour smoothness of the frames' shapes (the `smoothness` extra
// term, docs/problem.md; after Torresani et al. 2001's shape
// regularisation), one residual block per frame t and stencil: a point i and
// its Delaunay neighbours j (problems/delaunay_edges.h, SmoothnessStencil):
//
//   r = s · (S_t[:, i] − Σ_j w_ij S_t[:, j])
//     = s · Σ_m c_m Σ_k l_tk b_m,k,   3 residuals,
//
// c = (1, −w_i1, …, −w_in) the stencil's coefficients over its points m =
// (i, j_1, …, j_n), l_t the frame's K weights, b_m = [S_1[:,m]; …; S_K[:,m]]
// the basis column of point m (Model::basis, input units), s = sqrt(λ / F)
// (dimensionless; F the number of frames, λ ≥ 0 the term's weight). The
// weights w_ij sum to 1 and give
// the point's image position as an affine combination of its neighbours'
// when one does (problems/delaunay_edges.h), so the residual is the point's
// departure from the affine interpolation of its neighbours: zero on a shape
// that is an affine function of the image (a plane, seen at any depth and
// slant) wherever the point has three neighbours not on one line, so the
// term penalises the surface's bending, not its size or slant (a point on
// the outline with two neighbours, or one, is pulled towards them as well;
// a point outside its neighbours' hull extrapolates from them, with weights
// that can exceed 1). λ = 1 weighs a departure of one input unit, averaged
// over the frames, like a reprojection error of one input unit. A point
// that the images leave ambiguous (few observations) is pulled to the
// surface its neighbours span.
//
// Gauge: the term reads only the shapes, so it is invariant to the K × K
// gauge of the model (basis Q B, weights L Q⁻¹ give the same shapes), and
// (the coefficients summing to 0) to a translation of a frame's shape.
//
// Blocks: l_t (K), then b_m (3K) for each point of the stencil.
// Hand-written Jacobian:
//   ∂r/∂l_tk = s Σ_m c_m b_m,k,   ∂r/∂b_m,k = s c_m l_tk I₃.
#ifndef NRSFM_PROBLEMS_SMOOTHNESS_ERROR_H_
#define NRSFM_PROBLEMS_SMOOTHNESS_ERROR_H_

#include <ceres/cost_function.h>
#include <glog/logging.h>

#include <utility>
#include <vector>

#include "problems/jacobian_product.h"

namespace nrsfm {

class SmoothnessError final : public ceres::CostFunction,
                              public JacobianProduct {
 public:
  // `coefficients` c_m, one per point of the stencil (≥ 1 of them);
  // `scale` s.
  SmoothnessError(int num_bases, double scale, std::vector<double> coefficients)
      : num_bases_(num_bases),
        scale_(scale),
        coefficients_(std::move(coefficients)) {
    CHECK_GE(num_bases, 1);
    CHECK(!coefficients_.empty());
    set_num_residuals(3);
    mutable_parameter_block_sizes()->push_back(num_bases);
    for (std::size_t m = 0; m < coefficients_.size(); ++m) {
      mutable_parameter_block_sizes()->push_back(3 * num_bases);
    }
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* l = parameters[0];
    const int k3 = 3 * num_bases_;
    // d = s Σ_m c_m b_m (3K values): the Jacobian of the weights.
    double d[3 * kMaxBasesOnStack];
    std::vector<double> heap;
    double* difference = d;
    if (num_bases_ > kMaxBasesOnStack) {
      heap.resize(k3);
      difference = heap.data();
    }
    Difference(parameters, difference);
    residuals[0] = residuals[1] = residuals[2] = 0.0;
    for (int k = 0; k < num_bases_; ++k) {
      for (int c = 0; c < 3; ++c) residuals[c] += l[k] * difference[3 * k + c];
    }
    if (jacobians == nullptr) return true;
    if (jacobians[0] != nullptr) {  // 3 × K, row-major
      for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < num_bases_; ++k) {
          jacobians[0][c * num_bases_ + k] = difference[3 * k + c];
        }
      }
    }
    for (std::size_t m = 0; m < coefficients_.size(); ++m) {
      double* j = jacobians[m + 1];  // 3 × 3K, row-major
      if (j == nullptr) continue;
      const double sign = scale_ * coefficients_[m];
      for (int i = 0; i < 3 * k3; ++i) j[i] = 0.0;
      for (int k = 0; k < num_bases_; ++k) {
        for (int c = 0; c < 3; ++c) j[c * k3 + 3 * k + c] = sign * l[k];
      }
    }
    return true;
  }

  // The products from the parameters (problems/jacobian_product.h): the
  // stored Jacobian would be read 3 × (K + 3K n) values at a time, F times
  // per stencil.
  void AddJacobianProduct(double const* const* parameters,
                          double const* const* x, double* y) const override {
    const double* l = parameters[0];
    double sum[3] = {0.0, 0.0, 0.0};
    for (std::size_t m = 0; m < coefficients_.size(); ++m) {
      const double* b = parameters[m + 1];
      const double c_m = coefficients_[m];
      for (int k = 0; k < num_bases_; ++k) {
        for (int c = 0; c < 3; ++c) {
          const int e = 3 * k + c;
          double v = 0.0;
          if (x[0] != nullptr) v += b[e] * x[0][k];
          if (x[m + 1] != nullptr) v += l[k] * x[m + 1][e];
          sum[c] += c_m * v;
        }
      }
    }
    for (int c = 0; c < 3; ++c) y[c] += scale_ * sum[c];
  }

  void AddJacobianTransposeProduct(double const* const* parameters,
                                   const double* y,
                                   double* const* x) const override {
    const double* l = parameters[0];
    const double sy[3] = {scale_ * y[0], scale_ * y[1], scale_ * y[2]};
    for (std::size_t m = 0; m < coefficients_.size(); ++m) {
      const double* b = parameters[m + 1];
      const double c_m = coefficients_[m];
      for (int k = 0; k < num_bases_; ++k) {
        if (x[0] != nullptr) {
          double v = 0.0;
          for (int c = 0; c < 3; ++c) v += b[3 * k + c] * sy[c];
          x[0][k] += c_m * v;
        }
        if (x[m + 1] != nullptr) {
          for (int c = 0; c < 3; ++c) x[m + 1][3 * k + c] += c_m * l[k] * sy[c];
        }
      }
    }
  }

  // r = s · (Σ_m c_m B_m) l_t.
  bool GetBilinearForm(BilinearForm* form) const override {
    form->scale = scale_;
    form->num_bases = num_bases_;
    form->signs.assign(1, 1.0);
    form->signs.insert(form->signs.end(), coefficients_.begin(),
                       coefficients_.end());
    form->is_weights.assign(coefficients_.size() + 1, false);
    form->is_weights[0] = true;
    form->mask.clear();
    return true;
  }

  int num_bases() const { return num_bases_; }
  double scale() const { return scale_; }
  const std::vector<double>& coefficients() const { return coefficients_; }

 private:
  static constexpr int kMaxBasesOnStack = 32;

  // out (3K) = s Σ_m c_m b_m.
  void Difference(double const* const* parameters, double* out) const {
    const int k3 = 3 * num_bases_;
    for (int e = 0; e < k3; ++e) out[e] = 0.0;
    for (std::size_t m = 0; m < coefficients_.size(); ++m) {
      const double* b = parameters[m + 1];
      const double c_m = scale_ * coefficients_[m];
      for (int e = 0; e < k3; ++e) out[e] += c_m * b[e];
    }
  }

  int num_bases_;
  double scale_;
  std::vector<double> coefficients_;
};

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_SMOOTHNESS_ERROR_H_
