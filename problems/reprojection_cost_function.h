// The reprojection error of docs/problem.md with the library's one,
// hand-written, Jacobian (the tests compare it with the autodiff oracle of
// tests/problems/reprojection_error_oracle.h: same residual, same parameter
// blocks, same order):
//
//   r = sqrt(w_obs) · ( s · Π R(ω) X + T − w_tcp ),   X = Σ_k l_k b_k = B l
//
// with B = [b_1 … b_K] (3 × K, the basis column b_p reshaped). Then
//   ∂r/∂ω   = sqrt(w_obs) · s · Π ∂(R(ω) X)/∂ω    (2 × 3, ProjectedRotation)
//   ∂r/∂T   = sqrt(w_obs) · I_2                    (2 × 2)
//   ∂r/∂l   = sqrt(w_obs) · s · Π R B              (2 × K)
//   ∂r/∂b_k = sqrt(w_obs) · s · l_k · Π R          (2 × 3 per k)
//   ∂r/∂s   = sqrt(w_obs) · Π R X                  (2 × 1, scaled form only)
//
// Why: automatic differentiation carries all 3 + 2 + 4K (+1) derivatives
// through every multiplication of the shape sum (docs/performance.md).
//
// kNumBases = K fixed at compile time (fixed-size Eigen), or Eigen::Dynamic
// with K given at run time (the fallback above kMaxStaticBases).
#ifndef NRSFM_PROBLEMS_REPROJECTION_COST_FUNCTION_H_
#define NRSFM_PROBLEMS_REPROJECTION_COST_FUNCTION_H_

#include <ceres/cost_function.h>
#include <ceres/jet.h>
#include <ceres/rotation.h>
#include <glog/logging.h>

#include <Eigen/Core>
#include <vector>

namespace nrsfm {

// Largest K with a compile-time specialisation (problems/problem_builder.cc
// dispatches 1…kMaxStaticBases with a switch).
inline constexpr int kMaxStaticBases = 16;

// What a reprojection residual needs of its rotation block ω: Π R(ω) and its
// derivatives by ω_i (dual numbers through ceres::AngleAxisToRotationMatrix,
// exact at ω = 0). It is the same for every residual of a view, so a caller
// that evaluates many can form it once per view; formed here or inside
// Evaluate(), it is the same bits.
struct ProjectedRotation {
  Eigen::Matrix<double, 2, 3> projection;     // Π R
  Eigen::Matrix<double, 2, 3> derivative[3];  // ∂(Π R)/∂ω_i

  static ProjectedRotation FromAngleAxis(const double* omega) {
    using Jet3 = ceres::Jet<double, 3>;
    const Jet3 w[3] = {Jet3(omega[0], 0), Jet3(omega[1], 1), Jet3(omega[2], 2)};
    Jet3 rotation[9];  // column-major
    ceres::AngleAxisToRotationMatrix(w, rotation);
    ProjectedRotation out;
    for (int col = 0; col < 3; ++col) {
      for (int row = 0; row < 2; ++row) {
        const Jet3& entry = rotation[3 * col + row];
        out.projection(row, col) = entry.a;
        for (int i = 0; i < 3; ++i) out.derivative[i](row, col) = entry.v[i];
      }
    }
    return out;
  }
};

// The basis block's Jacobian of the reprojection error factors as
//   ∂r/∂b_k = l_k · A,   A = sqrt(w_obs) · s · Π R(ω)   (2 × 3),
// so a solver that multiplies by it many times
// (solvers/refine/structured_solver.h: every conjugate-gradient iteration) can
// keep A (6 numbers) instead of the 2 × 3K block and form J_b δb = A Σ_k l_k
// δb_k and J_bᵀ y = [l_k Aᵀ y]_k with the weights l it reads from the weights
// block.
class BasisJacobianFactor {
 public:
  static constexpr int kRotationSlot = 0;  // parameter block ω (3)
  static constexpr int kWeightsSlot = 2;   // parameter block l (K)
  static constexpr int kBasisSlot = 3;     // parameter block b_p (3K)

  virtual ~BasisJacobianFactor() = default;
  virtual int num_bases() const = 0;
  // sqrt(w_obs), the residual's weight.
  virtual double sqrt_weight() const = 0;
  // Evaluate() that also writes A (row-major 2 × 3) to `factor` when it is
  // not null; jacobians[kBasisSlot] may be null then (not computed).
  // `rotation`, when not null, must be ProjectedRotation::FromAngleAxis of
  // parameters[kRotationSlot] (it is then not formed again).
  virtual bool EvaluateWithBasisFactor(
      double const* const* parameters, double* residuals, double** jacobians,
      double* factor, const ProjectedRotation* rotation) const = 0;
};

template <int kNumBases>
class ReprojectionCostFunction final : public ceres::CostFunction,
                                       public BasisJacobianFactor {
 public:
  // `num_bases` must equal kNumBases unless kNumBases is Eigen::Dynamic.
  // `with_scale` adds the fifth block s (cameras c ≥ 1 of multi-camera data).
  ReprojectionCostFunction(int num_bases, bool with_scale,
                           const Eigen::Vector2d& observation,
                           double sqrt_weight)
      : num_bases_(num_bases),
        with_scale_(with_scale),
        observation_(observation),
        sqrt_weight_(sqrt_weight) {
    CHECK_GE(num_bases, 1);
    CHECK(kNumBases == Eigen::Dynamic || kNumBases == num_bases);
    set_num_residuals(2);
    std::vector<int>* sizes = mutable_parameter_block_sizes();
    *sizes = {3, 2, num_bases, 3 * num_bases};
    if (with_scale) sizes->push_back(1);
  }

  int num_bases() const override { return num_bases_; }
  double sqrt_weight() const override { return sqrt_weight_; }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    return EvaluateWithBasisFactor(parameters, residuals, jacobians, nullptr,
                                   nullptr);
  }

  bool EvaluateWithBasisFactor(
      double const* const* parameters, double* residuals, double** jacobians,
      double* factor, const ProjectedRotation* rotation) const override {
    // Eigen forbids a row-major 2 × 1 type; for K = 1 both layouts agree.
    using RowMajor2xK =
        Eigen::Matrix<double, 2, kNumBases,
                      kNumBases == 1 ? Eigen::ColMajor : Eigen::RowMajor>;
    const Eigen::Map<const Eigen::Matrix<double, kNumBases, 1>> weights(
        parameters[2], num_bases_);
    const Eigen::Map<const Eigen::Matrix<double, 3, kNumBases>> basis(
        parameters[3], 3, num_bases_);
    const double scale = with_scale_ ? parameters[4][0] : 1.0;
    const Eigen::Vector3d point = basis * weights;

    const ProjectedRotation formed =
        rotation == nullptr
            ? ProjectedRotation::FromAngleAxis(parameters[kRotationSlot])
            : ProjectedRotation();
    const ProjectedRotation& rot = rotation == nullptr ? formed : *rotation;
    const Eigen::Matrix<double, 2, 3>& projection = rot.projection;
    const Eigen::Vector2d projected = projection * point;
    const Eigen::Map<const Eigen::Vector2d> translation(parameters[1]);
    Eigen::Map<Eigen::Vector2d> residual(residuals);
    residual = sqrt_weight_ * (scale * projected + translation - observation_);

    const double scaled = sqrt_weight_ * scale;
    if (factor != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> a(factor);
      a = scaled * projection;
    }
    if (jacobians == nullptr) return true;
    if (jacobians[0] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> d_rotation(
          jacobians[0]);
      for (int i = 0; i < 3; ++i) {
        const Eigen::Matrix<double, 2, 3>& d = rot.derivative[i];
        for (int row = 0; row < 2; ++row) {
          d_rotation(row, i) =
              scaled * (d(row, 0) * point[0] + d(row, 1) * point[1] +
                        d(row, 2) * point[2]);
        }
      }
    }
    if (jacobians[1] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 2, 2, Eigen::RowMajor>> d_translation(
          jacobians[1]);
      d_translation = sqrt_weight_ * Eigen::Matrix2d::Identity();
    }
    if (jacobians[2] != nullptr) {
      Eigen::Map<RowMajor2xK> d_weights(jacobians[2], 2, num_bases_);
      d_weights = scaled * projection * basis;
    }
    if (jacobians[3] != nullptr) {
      for (int k = 0; k < num_bases_; ++k) {
        for (int row = 0; row < 2; ++row) {
          for (int col = 0; col < 3; ++col) {
            jacobians[3][row * 3 * num_bases_ + 3 * k + col] =
                scaled * weights[k] * projection(row, col);
          }
        }
      }
    }
    if (with_scale_ && jacobians[4] != nullptr) {
      Eigen::Map<Eigen::Vector2d> d_scale(jacobians[4]);
      d_scale = sqrt_weight_ * projected;
    }
    return true;
  }

 private:
  const int num_bases_;
  const bool with_scale_;
  const Eigen::Vector2d observation_;
  const double sqrt_weight_;
};

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_REPROJECTION_COST_FUNCTION_H_
