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
// Its products and Gram blocks are formed from the parameters
// (problems/jacobian_product.h): r = s · B_p (m ⊙ l_t) with the mask
// m = (0, 1, …, 1) is a bilinear form, so a solver can sum the blocks of
// all frames at once and store no Jacobian for them.
#ifndef NRSFM_PROBLEMS_DEFORMATION_ERROR_H_
#define NRSFM_PROBLEMS_DEFORMATION_ERROR_H_

#include <ceres/cost_function.h>
#include <glog/logging.h>

#include <Eigen/Core>
#include <cstddef>

#include "problems/jacobian_product.h"

namespace nrsfm {

class DeformationError final : public ceres::CostFunction,
                               public JacobianProduct {
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

  // y += s (B (m ⊙ x_l) + Σ_b (m ⊙ l)_b x_B[:, b]).
  void AddJacobianProduct(double const* const* parameters,
                          double const* const* x, double* y) const override {
    const double* weights = parameters[0];
    const double* basis = parameters[1];
    double sum[3] = {0.0, 0.0, 0.0};
    for (int b = 1; b < num_bases_; ++b) {
      for (int j = 0; j < 3; ++j) {
        if (x[0] != nullptr) sum[j] += basis[3 * b + j] * x[0][b];
        if (x[1] != nullptr) sum[j] += weights[b] * x[1][3 * b + j];
      }
    }
    for (int j = 0; j < 3; ++j) y[j] += sqrt_weight_ * sum[j];
  }

  void AddJacobianTransposeProduct(double const* const* parameters,
                                   const double* y,
                                   double* const* x) const override {
    const double* weights = parameters[0];
    const double* basis = parameters[1];
    const double sy[3] = {sqrt_weight_ * y[0], sqrt_weight_ * y[1],
                          sqrt_weight_ * y[2]};
    for (int b = 1; b < num_bases_; ++b) {
      if (x[0] != nullptr) {
        x[0][b] += basis[3 * b] * sy[0] + basis[3 * b + 1] * sy[1] +
                   basis[3 * b + 2] * sy[2];
      }
      if (x[1] != nullptr) {
        for (int j = 0; j < 3; ++j) x[1][3 * b + j] += weights[b] * sy[j];
      }
    }
  }

  bool ProvidesGram() const override { return true; }

  // With λ = m ⊙ l: J_lᵀJ_l = s² M BᵀB M, J_BᵀJ_B = s² (λ λᵀ) ⊗ I₃,
  // (J_lᵀJ_B)(i, 3c + d) = s² m_i B(d, i) λ_c; shape 1 (i or c = 0) is 0.
  void AddGram(double const* const* parameters, int a, int b, double* out,
               int ld) const override {
    const int k = num_bases_;
    const double s2 = sqrt_weight_ * sqrt_weight_;
    const double* weights = parameters[0];
    const double* basis = parameters[1];
    const auto at = [out, ld](int i, int j) -> double& {
      return out[i + static_cast<std::ptrdiff_t>(j) * ld];
    };
    if (a == 0 && b == 0) {
      for (int j = 1; j < k; ++j) {
        for (int i = 1; i < k; ++i) {
          const double* bi = basis + 3 * i;
          const double* bj = basis + 3 * j;
          at(i, j) += s2 * (bi[0] * bj[0] + bi[1] * bj[1] + bi[2] * bj[2]);
        }
      }
    } else if (a == 1 && b == 1) {
      for (int cj = 1; cj < k; ++cj) {
        for (int ci = 1; ci < k; ++ci) {
          const double v = s2 * weights[ci] * weights[cj];
          for (int d = 0; d < 3; ++d) at(3 * ci + d, 3 * cj + d) += v;
        }
      }
    } else {
      for (int i = 1; i < k; ++i) {
        for (int c = 1; c < k; ++c) {
          for (int d = 0; d < 3; ++d) {
            const double v = s2 * basis[3 * i + d] * weights[c];
            if (a == 0) {
              at(i, 3 * c + d) += v;
            } else {
              at(3 * c + d, i) += v;
            }
          }
        }
      }
    }
  }

  void AddGramDiagonal(double const* const* parameters, int a,
                       double* out) const override {
    const double s2 = sqrt_weight_ * sqrt_weight_;
    for (int c = 1; c < num_bases_; ++c) {
      if (a == 0) {
        const double* bc = parameters[1] + 3 * c;
        out[c] += s2 * (bc[0] * bc[0] + bc[1] * bc[1] + bc[2] * bc[2]);
      } else {
        const double l = parameters[0][c];
        for (int d = 0; d < 3; ++d) out[3 * c + d] += s2 * l * l;
      }
    }
  }

  // r = s · B_p (m ⊙ l_t), m = (0, 1, …, 1).
  bool GetBilinearForm(BilinearForm* form) const override {
    *form =
        BilinearForm{sqrt_weight_, num_bases_, {1.0, 1.0}, {true, false}, {}};
    form->mask.assign(num_bases_, 1.0);
    form->mask[0] = 0.0;
    return true;
  }

 private:
  const int num_bases_;
  const double sqrt_weight_;
};

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_DEFORMATION_ERROR_H_
