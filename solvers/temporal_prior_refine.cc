#include "solvers/temporal_prior_refine.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include <ceres/cost_function.h>
#include <ceres/jet.h>
#include <ceres/rotation.h>
#include <ceres/solver.h>
#include <glog/logging.h>
#include <Eigen/Core>

#include "core/metrics.h"
#include "problems/linear_solver_choice.h"
#include "problems/problem_builder.h"

namespace nrsfm {
namespace {

using Clock = std::chrono::steady_clock;
using RowMajorMatrix =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// R(ω) and ∂R/∂ω_i (i = 0, 1, 2) through dual numbers.
struct RotationWithDerivative {
  explicit RotationWithDerivative(const double* omega) {
    using Jet3 = ceres::Jet<double, 3>;
    const Jet3 w[3] = {Jet3(omega[0], 0), Jet3(omega[1], 1), Jet3(omega[2], 2)};
    Jet3 r[9];  // column-major
    ceres::AngleAxisToRotationMatrix(w, r);
    for (int col = 0; col < 3; ++col) {
      for (int row = 0; row < 3; ++row) {
        value(row, col) = r[3 * col + row].a;
        for (int i = 0; i < 3; ++i) derivative[i](row, col) = r[3 * col + row].v[i];
      }
    }
  }
  Eigen::Matrix3d value;
  Eigen::Matrix3d derivative[3];
};

// r = sqrt(λ) (R(ω1) B l1 − R(ω0) B l0), blocks ω0, ω1, l0, l1, b (3K).
class CameraShapeSmoothness final : public ceres::CostFunction {
 public:
  CameraShapeSmoothness(int num_bases, double sqrt_weight)
      : num_bases_(num_bases), sqrt_weight_(sqrt_weight) {
    set_num_residuals(3);
    *mutable_parameter_block_sizes() = {3, 3, num_bases, num_bases, 3 * num_bases};
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int k = num_bases_;
    const Eigen::Map<const Eigen::VectorXd> l0(parameters[2], k);
    const Eigen::Map<const Eigen::VectorXd> l1(parameters[3], k);
    const Eigen::Map<const Eigen::MatrixXd> basis(parameters[4], 3, k);
    const Eigen::Vector3d x0 = basis * l0;
    const Eigen::Vector3d x1 = basis * l1;
    const RotationWithDerivative r0(parameters[0]);
    const RotationWithDerivative r1(parameters[1]);
    Eigen::Map<Eigen::Vector3d> residual(residuals);
    residual = sqrt_weight_ * (r1.value * x1 - r0.value * x0);
    if (jacobians == nullptr) return true;
    if (jacobians[0] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> j(jacobians[0]);
      for (int i = 0; i < 3; ++i) j.col(i) = -sqrt_weight_ * r0.derivative[i] * x0;
    }
    if (jacobians[1] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> j(jacobians[1]);
      for (int i = 0; i < 3; ++i) j.col(i) = sqrt_weight_ * r1.derivative[i] * x1;
    }
    if (jacobians[2] != nullptr) {
      Eigen::Map<RowMajorMatrix>(jacobians[2], 3, k) =
          -sqrt_weight_ * r0.value * basis;
    }
    if (jacobians[3] != nullptr) {
      Eigen::Map<RowMajorMatrix>(jacobians[3], 3, k) =
          sqrt_weight_ * r1.value * basis;
    }
    if (jacobians[4] != nullptr) {
      Eigen::Map<RowMajorMatrix> j(jacobians[4], 3, 3 * k);
      for (int b = 0; b < k; ++b) {
        j.block<3, 3>(0, 3 * b) =
            sqrt_weight_ * (l1[b] * r1.value - l0[b] * r0.value);
      }
    }
    return true;
  }

 private:
  const int num_bases_;
  const double sqrt_weight_;
};

// r = sqrt(μ) B l = sqrt(μ) S_t[:, p], blocks l (K), b (3K).
class ShapeMagnitude final : public ceres::CostFunction {
 public:
  ShapeMagnitude(int num_bases, double sqrt_weight)
      : num_bases_(num_bases), sqrt_weight_(sqrt_weight) {
    set_num_residuals(3);
    *mutable_parameter_block_sizes() = {num_bases, 3 * num_bases};
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int k = num_bases_;
    const Eigen::Map<const Eigen::VectorXd> l(parameters[0], k);
    const Eigen::Map<const Eigen::MatrixXd> basis(parameters[1], 3, k);
    Eigen::Map<Eigen::Vector3d> residual(residuals);
    residual = sqrt_weight_ * (basis * l);
    if (jacobians == nullptr) return true;
    if (jacobians[0] != nullptr) {
      Eigen::Map<RowMajorMatrix>(jacobians[0], 3, k) = sqrt_weight_ * basis;
    }
    if (jacobians[1] != nullptr) {
      Eigen::Map<RowMajorMatrix> j(jacobians[1], 3, 3 * k);
      j.setZero();
      for (int b = 0; b < k; ++b) {
        j.block<3, 3>(0, 3 * b).diagonal().setConstant(sqrt_weight_ * l[b]);
      }
    }
    return true;
  }

 private:
  const int num_bases_;
  const double sqrt_weight_;
};

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

Status TemporalPriorOptions::Check() const {
  if (!(camera_shape_weight >= 0.0) || !std::isfinite(camera_shape_weight)) {
    return Status::Error(
        "temporal prior: camera_shape_weight must be finite and >= 0, got " +
        std::to_string(camera_shape_weight));
  }
  if (!(shape_magnitude_weight >= 0.0) || !std::isfinite(shape_magnitude_weight)) {
    return Status::Error(
        "temporal prior: shape_magnitude_weight must be finite and >= 0, got " +
        std::to_string(shape_magnitude_weight));
  }
  return Status::OK();
}

Status RefineWithTemporalPrior(const RefineOptions& options,
                               const TemporalPriorOptions& prior,
                               const Measurements& measurements, Model* model,
                               RefineSummary* summary) {
  CHECK(model != nullptr);
  CHECK(summary != nullptr);
  NRSFM_RETURN_IF_ERROR(prior.Check());
  if (prior.camera_shape_weight == 0.0 && prior.shape_magnitude_weight == 0.0) {
    return Refine(options, measurements, model, summary);
  }
  const Clock::time_point start = Clock::now();
  *summary = RefineSummary();
  NRSFM_RETURN_IF_ERROR(options.Check());
  const Model input = *model;
  ProblemOptions problem_options;
  problem_options.robust_loss = options.robust_loss;
  problem_options.robust_scale = options.robust_scale;
  ProblemBuilder builder(&measurements, model);
  NRSFM_RETURN_IF_ERROR(builder.AddReprojectionTerms(problem_options)
                            .WithContext("temporal prior refine"));
  summary->num_residual_blocks = builder.num_reprojection_terms();
  summary->initial_reprojection_rms = ReprojectionRms(measurements, *model);
  ceres::Problem* problem = builder.problem();
  const double sqrt_weight = std::sqrt(prior.camera_shape_weight);
  const double sqrt_magnitude = std::sqrt(prior.shape_magnitude_weight);
  for (int t = 0; t < model->num_frames && sqrt_magnitude > 0.0; ++t) {
    for (int p = 0; p < model->num_points; ++p) {
      double* basis = builder.BasisBlock(p);
      if (!problem->HasParameterBlock(basis) ||
          !problem->HasParameterBlock(builder.WeightsBlock(t))) {
        continue;
      }
      problem->AddResidualBlock(new ShapeMagnitude(model->num_bases, sqrt_magnitude),
                                nullptr, builder.WeightsBlock(t), basis);
    }
  }
  for (int t = 0; t + 1 < model->num_frames && sqrt_weight > 0.0; ++t) {
    double* omega0 = builder.RotationBlock(t, 0);
    double* omega1 = builder.RotationBlock(t + 1, 0);
    if (!problem->HasParameterBlock(omega0) || !problem->HasParameterBlock(omega1)) {
      continue;
    }
    for (int p = 0; p < model->num_points; ++p) {
      double* basis = builder.BasisBlock(p);
      if (!problem->HasParameterBlock(basis)) continue;
      problem->AddResidualBlock(
          new CameraShapeSmoothness(model->num_bases, sqrt_weight), nullptr,
          {omega0, omega1, builder.WeightsBlock(t), builder.WeightsBlock(t + 1),
           basis});
    }
  }

  ceres::Solver::Options solver_options;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = options.function_tolerance;
  solver_options.gradient_tolerance = options.gradient_tolerance;
  solver_options.parameter_tolerance = options.parameter_tolerance;
  if (options.max_seconds > 0.0) {
    solver_options.max_solver_time_in_seconds = options.max_seconds;
  }
  solver_options.num_threads = options.num_threads;
  solver_options.logging_type = ceres::SILENT;
  LinearSolverChoice used = LinearSolverChoice::kAuto;
  NRSFM_RETURN_IF_ERROR(ConfigureLinearSolver(options.linear_solver, &builder,
                                              &solver_options, &used)
                            .WithContext("temporal prior refine"));
  summary->linear_solver = LinearSolverName(used);
  std::string invalid;
  if (!solver_options.IsValid(&invalid)) {
    return Status::Error("temporal prior refine: invalid Ceres options: " + invalid);
  }
  summary->build_seconds = SecondsSince(start);
  ceres::Solver::Summary ceres_summary;
  ceres::Solve(solver_options, problem, &ceres_summary);
  summary->message = ceres_summary.message;
  summary->initial_cost = ceres_summary.initial_cost;
  summary->final_cost = ceres_summary.final_cost;
  summary->iterations =
      std::max(0, static_cast<int>(ceres_summary.iterations.size()) - 1);
  summary->preprocessor_seconds = ceres_summary.preprocessor_time_in_seconds;
  summary->residual_seconds = ceres_summary.residual_evaluation_time_in_seconds;
  summary->jacobian_seconds = ceres_summary.jacobian_evaluation_time_in_seconds;
  summary->linear_solver_seconds = ceres_summary.linear_solver_time_in_seconds;
  summary->minimizer_seconds = ceres_summary.minimizer_time_in_seconds;
  summary->usable = ceres_summary.IsSolutionUsable();
  if (summary->usable && !model->Validate().ok()) {
    summary->usable = false;
    summary->message = "the refined model is not finite (" + summary->message + ")";
  }
  if (!summary->usable) {
    *model = input;
    summary->final_cost = summary->initial_cost;
  }
  summary->reprojection_rms = ReprojectionRms(measurements, *model);
  summary->seconds = SecondsSince(start);
  return Status::OK();
}

}  // namespace nrsfm
