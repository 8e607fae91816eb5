// The deformation prior (the `deformation` extra term, docs/problem.md): one
// residual block per frame t and point p,
//
//   r = sqrt(λ_D) · Σ_{k ≥ 2} l_tk S_k[:, p],        3 residuals,
//
// the part of the object-frame shape S_t that is not a multiple of basis
// shape 1. Over the gauges of the model (K × K mixing of weights and basis)
// its minimum is Σ_t min_c ‖S_t − c S̄‖², the deformation of each frame away
// from one rigid shape S̄ up to the frame's scale (a weak-perspective camera's
// scale is absorbed in l_t1, so the prior does not penalise it). λ_D is
// dimensionless: λ_D = 1 weighs a point's 3D deformation like a reprojection
// error of the same length. λ_D → ∞ gives the rigid model with per-frame
// scale; it is the zero-mean Gaussian prior on the deformation coefficients
// of probabilistic PCA (Torresani et al. 2008) in MAP form. Invariant to the
// global rotation and to the relative scale of weights and basis.
//
// Blocks: l_t (K), b_p (3K, = [S_1[:, p]; …; S_K[:, p]]). Linear in each:
// J_{l_t} = sqrt(λ_D) [0, S_2[:, p], …, S_K[:, p]] (3 × K),
// J_{b_p} = sqrt(λ_D) [0, l_t2 I_3, …, l_tK I_3] (3 × 3K). K at run time.
#ifndef NRSFM_PROBLEMS_DEFORMATION_ERROR_H_
#define NRSFM_PROBLEMS_DEFORMATION_ERROR_H_

#include <ceres/cost_function.h>
#include <glog/logging.h>

#include <Eigen/Core>

namespace nrsfm {

class DeformationError final : public ceres::CostFunction {
 public:
  DeformationError(int num_bases, double sqrt_weight)
      : num_bases_(num_bases), sqrt_weight_(sqrt_weight) {
    CHECK_GE(num_bases, 1);
    set_num_residuals(3);
    *mutable_parameter_block_sizes() = {num_bases, 3 * num_bases};
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int k = num_bases_;
    const double s = sqrt_weight_;
    const double* weights = parameters[0];
    const double* basis = parameters[1];  // shape b: basis[3b .. 3b + 2]
    for (int j = 0; j < 3; ++j) residuals[j] = 0.0;
    for (int b = 1; b < k; ++b) {
      for (int j = 0; j < 3; ++j)
        residuals[j] += s * weights[b] * basis[3 * b + j];
    }
    if (jacobians == nullptr) return true;
    if (jacobians[0] != nullptr) {  // 3 × K, row-major
      for (int j = 0; j < 3; ++j) {
        jacobians[0][j * k] = 0.0;
        for (int b = 1; b < k; ++b)
          jacobians[0][j * k + b] = s * basis[3 * b + j];
      }
    }
    if (jacobians[1] != nullptr) {  // 3 × 3K, row-major
      double* jb = jacobians[1];
      for (int i = 0; i < 9 * k; ++i) jb[i] = 0.0;
      for (int b = 1; b < k; ++b) {
        for (int j = 0; j < 3; ++j) jb[j * 3 * k + 3 * b + j] = s * weights[b];
      }
    }
    return true;
  }

 private:
  const int num_bases_;
  const double sqrt_weight_;
};

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_DEFORMATION_ERROR_H_
