// Temporal smoothness priors for video-like input (the temporal,
// temporal_rotations, temporal_shape and rotation_acceleration extra terms,
// docs/problem.md), one residual block per pair of consecutive frames
// (t − 1, t), t = 1 … F − 1:
//
//   weights:   r = sqrt(λ_l) · (l_t − l_{t−1}),                 K residuals
//   rotations: r = sqrt(λ_R) · log( R(ω_tc) R(ω_{t−1,c})ᵀ ),    3 residuals,
//              one block per camera c
//   shapes:    r = sqrt(λ_S) · (S_t[:, p] − S_{t−1}[:, p]),     3 residuals,
//              one block per point p, S_t = Σ_k l_tk S_k in the object frame
//   angular acceleration, t = 1 … F − 2, one block per camera c:
//              r = sqrt(λ_A) · σ · ( log(R_{t+1} R_tᵀ) − log(R_t R_{t−1}ᵀ) ),
//              3 residuals; σ = the spread of the data
//              (Measurements::ImageSpreadRms), so λ_A is dimensionless
//
// l_t the frame's basis weights (Model::weights.col(t), dimensionless), ω_tc
// the view's angle-axis (radians); log = the angle-axis of the relative
// rotation, whose norm is the angle turned between the two frames.
// Weights: λ_l in (input units)² per unit of weight change; λ_R in (input
// units / rad)²: λ = 1 weighs a weight change of 1, or a turn of 1 rad,
// between consecutive frames like a reprojection error of one input unit.
// Angular acceleration: λ_A = 1 weighs a change of angular velocity of
// 1 rad/frame like a reprojection error of σ — about what such a change of
// the turn does to the image of the object. It favours a constant angular
// velocity rather than a slow one, so unlike the first-order rotation prior
// it does not pull a steadily turning camera towards rest (and towards the
// depth-reversed reading of the sequence that a turn slowed to zero allows).
// Shapes: λ_S is dimensionless (the residual is a 3D displacement in input
// units, like a reprojection error): λ_S = 1 weighs a point's 3D move
// between consecutive frames like a reprojection error of the same length.
// The rotation and shape priors are invariant to every gauge of the model
// (global rotation, K × K mixing of weights and basis, their relative
// scale); the weights prior is not invariant to the scale gauge (it favours
// smaller weights and a larger basis), so keep λ_l small against the data
// term. The shape prior is the one that constrains depth: with K near P/3
// the images fit to round-off for a whole family of depths, and of those it
// picks the object-frame motion that is slowest (the smooth-trajectory
// assumption of trajectory-basis methods, Akhter et al. 2008). Each of its
// blocks holds one point block, so the points stay Schur-eliminable.
#ifndef NRSFM_PROBLEMS_TEMPORAL_ERROR_H_
#define NRSFM_PROBLEMS_TEMPORAL_ERROR_H_

#include <ceres/autodiff_cost_function.h>
#include <ceres/cost_function.h>
#include <ceres/dynamic_autodiff_cost_function.h>
#include <glog/logging.h>

#include <Eigen/Core>

#include "problems/jacobian_product.h"
#include "problems/relative_rotation.h"

namespace nrsfm {

// Blocks: l_t (K), l_{t−1} (K). K at run time.
class WeightsTemporalError {
 public:
  WeightsTemporalError(int num_bases, double sqrt_weight)
      : num_bases_(num_bases), sqrt_weight_(sqrt_weight) {}

  template <typename T>
  bool operator()(T const* const* parameters, T* residuals) const {
    for (int k = 0; k < num_bases_; ++k) {
      residuals[k] = sqrt_weight_ * (parameters[0][k] - parameters[1][k]);
    }
    return true;
  }

  // Caller owns the result.
  static ceres::CostFunction* Create(int num_bases, double sqrt_weight) {
    CHECK_GE(num_bases, 1);
    auto* cost = new ceres::DynamicAutoDiffCostFunction<WeightsTemporalError>(
        new WeightsTemporalError(num_bases, sqrt_weight));
    cost->AddParameterBlock(num_bases);
    cost->AddParameterBlock(num_bases);
    cost->SetNumResiduals(num_bases);
    return cost;
  }

 private:
  int num_bases_;
  double sqrt_weight_;
};

// Blocks: ω_tc (3), ω_{t−1,c} (3).
class RotationTemporalError {
 public:
  explicit RotationTemporalError(double sqrt_weight)
      : sqrt_weight_(sqrt_weight) {}

  template <typename T>
  bool operator()(const T* rotation, const T* previous_rotation,
                  T* residuals) const {
    RelativeAngleAxis<T>(rotation, previous_rotation, nullptr, residuals);
    for (int i = 0; i < 3; ++i) residuals[i] *= sqrt_weight_;
    return true;
  }

  // Caller owns the result.
  static ceres::CostFunction* Create(double sqrt_weight) {
    return new ceres::AutoDiffCostFunction<RotationTemporalError, 3, 3, 3>(
        new RotationTemporalError(sqrt_weight));
  }

 private:
  double sqrt_weight_;
};

// Blocks: ω_{t+1,c}, ω_tc, ω_{t−1,c} (3 each). `scale` = sqrt(λ_A) · σ.
class RotationAccelerationError {
 public:
  explicit RotationAccelerationError(double scale) : scale_(scale) {}

  template <typename T>
  bool operator()(const T* next, const T* rotation, const T* previous,
                  T* residuals) const {
    T forward[3];
    T backward[3];
    RelativeAngleAxis<T>(next, rotation, nullptr, forward);
    RelativeAngleAxis<T>(rotation, previous, nullptr, backward);
    for (int i = 0; i < 3; ++i)
      residuals[i] = scale_ * (forward[i] - backward[i]);
    return true;
  }

  // Caller owns the result.
  static ceres::CostFunction* Create(double scale) {
    return new ceres::AutoDiffCostFunction<RotationAccelerationError, 3, 3, 3,
                                           3>(
        new RotationAccelerationError(scale));
  }

 private:
  double scale_;
};

// Blocks: l_t (K), l_{t−1} (K), b_p (3K, = [S_1[:, p]; …; S_K[:, p]]).
// Linear in each block: r = sqrt(λ_S) B_p (l_t − l_{t−1}) with B_p the 3 × K
// matrix whose column k is S_k[:, p]; analytic Jacobians, K at run time.
// The products with its Jacobian are also formed from the parameters
// (problems/jacobian_product.h): J_{l_t} = −J_{l_{t−1}} = sqrt(λ_S) B_p and
// J_{b_p} = sqrt(λ_S) (l_t − l_{t−1})ᵀ ⊗ I_3.
class ShapeTemporalError final : public ceres::CostFunction,
                                 public JacobianProduct {
 public:
  ShapeTemporalError(int num_bases, double sqrt_weight)
      : num_bases_(num_bases), sqrt_weight_(sqrt_weight) {
    CHECK_GE(num_bases, 1);
    set_num_residuals(3);
    *mutable_parameter_block_sizes() = {num_bases, num_bases, 3 * num_bases};
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    using RowMajor3X =
        Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>;
    const int k = num_bases_;
    const Eigen::Map<const Eigen::VectorXd> weights(parameters[0], k);
    const Eigen::Map<const Eigen::VectorXd> previous(parameters[1], k);
    const Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic>> basis(
        parameters[2], 3, k);
    const Eigen::VectorXd change = weights - previous;
    Eigen::Map<Eigen::Vector3d> residual(residuals);
    residual = sqrt_weight_ * (basis * change);
    if (jacobians == nullptr) return true;
    if (jacobians[0] != nullptr) {
      Eigen::Map<RowMajor3X>(jacobians[0], 3, k) = sqrt_weight_ * basis;
    }
    if (jacobians[1] != nullptr) {
      Eigen::Map<RowMajor3X>(jacobians[1], 3, k) = -sqrt_weight_ * basis;
    }
    if (jacobians[2] != nullptr) {
      Eigen::Map<RowMajor3X> j(jacobians[2], 3, 3 * k);
      j.setZero();
      for (int b = 0; b < k; ++b) {
        j.block<3, 3>(0, 3 * b).diagonal().setConstant(sqrt_weight_ *
                                                       change[b]);
      }
    }
    return true;
  }

  void AddJacobianProduct(double const* const* parameters,
                          double const* const* x, double* y) const override {
    const int k = num_bases_;
    const double s = sqrt_weight_;
    const double* basis = parameters[2];  // column b: basis[3b .. 3b + 2]
    double sum[3] = {0.0, 0.0, 0.0};
    for (int b = 0; b < k; ++b) {
      const double dl =
          (x[0] != nullptr ? x[0][b] : 0.0) - (x[1] != nullptr ? x[1][b] : 0.0);
      const double change = parameters[0][b] - parameters[1][b];
      for (int j = 0; j < 3; ++j) {
        sum[j] += basis[3 * b + j] * dl;
        if (x[2] != nullptr) sum[j] += change * x[2][3 * b + j];
      }
    }
    for (int j = 0; j < 3; ++j) y[j] += s * sum[j];
  }

  bool ProvidesGram() const override { return true; }

  // r = s · B (l_t − l_(t−1)).
  bool GetBilinearForm(BilinearForm* form) const override {
    *form = BilinearForm{
        sqrt_weight_, num_bases_, {1.0, -1.0, 1.0}, {true, true, false}, {}};
    return true;
  }

  // With J_0 = s B, J_1 = −s B (3 × K) and J_2 = s (Δlᵀ ⊗ I₃) (3 × 3K),
  // Δl = l_t − l_{t−1}: J_0ᵀJ_0 = J_1ᵀJ_1 = −J_0ᵀJ_1 = s² BᵀB,
  // J_2ᵀJ_2 = s² (Δl Δlᵀ) ⊗ I₃, J_0ᵀJ_2 = −J_1ᵀJ_2 = s² [Δl_c B(j, i)].
  void AddGram(double const* const* parameters, int a, int b, double* out,
               int ld) const override {
    const int k = num_bases_;
    const double s2 = sqrt_weight_ * sqrt_weight_;
    const double* basis = parameters[2];  // column c: basis[3c .. 3c + 2]
    if (a < 2 && b < 2) {
      const double sign = a == b ? s2 : -s2;
      for (int j = 0; j < k; ++j) {
        for (int i = 0; i < k; ++i) {
          const double* bi = basis + 3 * i;
          const double* bj = basis + 3 * j;
          out[i + static_cast<std::ptrdiff_t>(j) * ld] +=
              sign * (bi[0] * bj[0] + bi[1] * bj[1] + bi[2] * bj[2]);
        }
      }
      return;
    }
    const auto change = [parameters](int c) {
      return parameters[0][c] - parameters[1][c];
    };
    if (a == 2 && b == 2) {
      for (int cj = 0; cj < k; ++cj) {
        for (int ci = 0; ci < k; ++ci) {
          const double v = s2 * change(ci) * change(cj);
          for (int d = 0; d < 3; ++d) {
            out[3 * ci + d + static_cast<std::ptrdiff_t>(3 * cj + d) * ld] += v;
          }
        }
      }
      return;
    }
    // One of a, b is 2, the other 0 or 1: entry (i, 3c + d) of J_0ᵀJ_2 is
    // s² B(d, i) Δl_c.
    const int weights_block = a == 2 ? b : a;
    const double sign = weights_block == 0 ? s2 : -s2;
    for (int i = 0; i < k; ++i) {
      for (int c = 0; c < k; ++c) {
        for (int d = 0; d < 3; ++d) {
          const double v = sign * basis[3 * i + d] * change(c);
          if (a == 2) {
            out[3 * c + d + static_cast<std::ptrdiff_t>(i) * ld] += v;
          } else {
            out[i + static_cast<std::ptrdiff_t>(3 * c + d) * ld] += v;
          }
        }
      }
    }
  }

  void AddGramDiagonal(double const* const* parameters, int a,
                       double* out) const override {
    const int k = num_bases_;
    const double s2 = sqrt_weight_ * sqrt_weight_;
    for (int c = 0; c < k; ++c) {
      if (a < 2) {
        const double* bc = parameters[2] + 3 * c;
        out[c] += s2 * (bc[0] * bc[0] + bc[1] * bc[1] + bc[2] * bc[2]);
      } else {
        const double change = parameters[0][c] - parameters[1][c];
        for (int d = 0; d < 3; ++d) out[3 * c + d] += s2 * change * change;
      }
    }
  }

  void AddJacobianTransposeProduct(double const* const* parameters,
                                   const double* y,
                                   double* const* x) const override {
    const int k = num_bases_;
    const double s = sqrt_weight_;
    const double* basis = parameters[2];
    const double sy[3] = {s * y[0], s * y[1], s * y[2]};
    for (int b = 0; b < k; ++b) {
      if (x[0] != nullptr || x[1] != nullptr) {
        const double dot = basis[3 * b] * sy[0] + basis[3 * b + 1] * sy[1] +
                           basis[3 * b + 2] * sy[2];
        if (x[0] != nullptr) x[0][b] += dot;
        if (x[1] != nullptr) x[1][b] -= dot;
      }
      if (x[2] != nullptr) {
        const double change = parameters[0][b] - parameters[1][b];
        for (int j = 0; j < 3; ++j) x[2][3 * b + j] += change * sy[j];
      }
    }
  }

 private:
  const int num_bases_;
  const double sqrt_weight_;
};

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_TEMPORAL_ERROR_H_
