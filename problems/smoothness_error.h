// Delaunay-neighbour smoothness of the basis (the `smoothness` extra term,
// docs/problem.md; after Torresani et al. 2001's shape regularisation), one
// residual block per neighbour edge (i, j) (problems/delaunay_edges.h):
//
//   r = sqrt(λ) · α_ij · (b_i − b_j),   3K residuals,
//
// b_p = [S_1[:,p]; …; S_K[:,p]] the basis column of point p (Model::basis,
// input units), α_ij the edge weight (dimensionless, ~1 for a typical edge),
// λ ≥ 0 the term's weight (dimensionless: λ = 1 weighs a basis difference
// like a reprojection error of the same size). The cost ½ λ α² ||b_i − b_j||²
// pulls a point towards its neighbours in every basis shape, so a point that
// the images leave ambiguous (few observations) takes its neighbours' depth.
//
// Gauge: the term is not invariant to the scale gauge of the model (basis
// × a, weights ÷ a leave the data term unchanged and multiply this cost by
// a²), so it slowly favours a smaller basis with larger weights; keep λ
// small against the data term (≤ ~0.1) and compare shapes, not bases.
//
// Blocks: b_i (3K), b_j (3K). Linear in the blocks; automatic
// differentiation with K at run time (DynamicAutoDiffCostFunction).
#ifndef NRSFM_PROBLEMS_SMOOTHNESS_ERROR_H_
#define NRSFM_PROBLEMS_SMOOTHNESS_ERROR_H_

#include <ceres/dynamic_autodiff_cost_function.h>
#include <glog/logging.h>

namespace nrsfm {

class SmoothnessError {
 public:
  // `scale` = sqrt(λ) · α_ij.
  SmoothnessError(int num_bases, double scale)
      : num_bases_(num_bases), scale_(scale) {}

  template <typename T>
  bool operator()(T const* const* parameters, T* residuals) const {
    const T* b_i = parameters[0];
    const T* b_j = parameters[1];
    for (int r = 0; r < 3 * num_bases_; ++r) {
      residuals[r] = scale_ * (b_i[r] - b_j[r]);
    }
    return true;
  }

  // Caller owns the result.
  static ceres::CostFunction* Create(int num_bases, double sqrt_weight,
                                     double alpha) {
    CHECK_GE(num_bases, 1);
    auto* cost = new ceres::DynamicAutoDiffCostFunction<SmoothnessError>(
        new SmoothnessError(num_bases, sqrt_weight * alpha));
    cost->AddParameterBlock(3 * num_bases);
    cost->AddParameterBlock(3 * num_bases);
    cost->SetNumResiduals(3 * num_bases);
    return cost;
  }

 private:
  int num_bases_;
  double scale_;
};

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_SMOOTHNESS_ERROR_H_
