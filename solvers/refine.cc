#include "solvers/refine.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include <ceres/iteration_callback.h>
#include <ceres/solver.h>
#include <glog/logging.h>

#include "core/metrics.h"
#include "problems/extra_terms.h"

namespace nrsfm {
namespace {

using Clock = std::chrono::steady_clock;

// LM's first radius (Ceres' default is 1e4). The gauge freedoms make the
// nearly undamped first steps huge and rejected: from the closed-form start
// (bench/refine_benchmark.cc cases, same final costs) 1e4 took 14 / 5 / 13 /
// 13 / 9 / 6 / 11 iterations, 1e2 took 9 / 5 / 10 / 10 / 10 / 5 / 11
// (drink-sized K = 12 first).
constexpr double kInitialTrustRegionRadius = 1e2;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Forwards every LM iteration to the user's callback and to VLOG(1).
class ProgressCallback : public ceres::IterationCallback {
 public:
  explicit ProgressCallback(const RefineOptions& options) : options_(options) {}

  ceres::CallbackReturnType operator()(
      const ceres::IterationSummary& summary) override {
    Report(summary);
    return ceres::SOLVER_CONTINUE;
  }

  // Ceres does not run the callbacks for the iteration that terminates the
  // solve; this reports the iterations the callback has not seen.
  void ReportRemaining(const ceres::Solver::Summary& summary) {
    for (const ceres::IterationSummary& iteration : summary.iterations) {
      if (iteration.iteration > last_reported_) Report(iteration);
    }
  }

 private:
  void Report(const ceres::IterationSummary& summary) {
    last_reported_ = summary.iteration;
    const IterationReport report{summary.iteration, summary.cost,
                                 summary.cumulative_time_in_seconds};
    if (options_.verbosity >= 1) {
      VLOG(1) << "refine: iteration " << report.iteration << " cost "
              << report.cost << (summary.step_is_successful ? "" : " (rejected)")
              << " linear solver iterations "
              << summary.linear_solver_iterations << " time " << report.seconds
              << " s";
    }
    if (options_.progress) options_.progress(report);
  }

  const RefineOptions& options_;
  int last_reported_ = -1;
};

}  // namespace

Status RefineOptions::Check() const {
  std::ostringstream msg;
  if (max_iterations < 0) {
    msg << "max_iterations must be >= 0, got " << max_iterations;
  } else if (!(function_tolerance >= 0.0) || !(gradient_tolerance >= 0.0) ||
             !(parameter_tolerance >= 0.0)) {
    msg << "tolerances must be >= 0, got function " << function_tolerance
        << ", gradient " << gradient_tolerance << ", parameter "
        << parameter_tolerance;
  } else if (!(max_seconds >= 0.0)) {
    msg << "max_seconds must be >= 0, got " << max_seconds;
  } else if (num_threads < 1) {
    msg << "num_threads must be >= 1, got " << num_threads;
  } else if (!(robust_scale > 0.0) || !std::isfinite(robust_scale)) {
    msg << "robust_scale must be positive and finite, got " << robust_scale;
  } else if (!refine_rotations && !refine_translations && !refine_weights &&
             !refine_basis && !refine_scales) {
    msg << "nothing to refine: every refine_* flag is false";
  } else if (!(smoothness_weight >= 0.0) || !std::isfinite(smoothness_weight) ||
             !(rigidity_weight >= 0.0) || !std::isfinite(rigidity_weight) ||
             !(temporal_weights_weight >= 0.0) ||
             !std::isfinite(temporal_weights_weight) ||
             !(temporal_rotations_weight >= 0.0) ||
             !std::isfinite(temporal_rotations_weight) ||
             !(temporal_shape_weight >= 0.0) ||
             !std::isfinite(temporal_shape_weight) ||
             !(rotation_acceleration_weight >= 0.0) ||
             !std::isfinite(rotation_acceleration_weight)) {
    msg << "term weights must be finite and >= 0, got smoothness "
        << smoothness_weight << ", rigidity " << rigidity_weight
        << ", temporal weights " << temporal_weights_weight
        << ", temporal rotations " << temporal_rotations_weight
        << ", temporal shape " << temporal_shape_weight
        << ", rotation acceleration " << rotation_acceleration_weight;
  } else if (smoothness_reference_frame < -1) {
    msg << "smoothness_reference_frame must be -1 (auto) or a frame, got "
        << smoothness_reference_frame;
  } else if (verbosity < 0) {
    msg << "verbosity must be >= 0, got " << verbosity;
  }
  if (msg.str().empty()) return Status::OK();
  return Status::Error("refine options: " + msg.str());
}

Status Refine(const RefineOptions& options, const Measurements& measurements,
              Model* model, RefineSummary* summary) {
  CHECK(model != nullptr);
  CHECK(summary != nullptr);
  const Clock::time_point start = Clock::now();
  *summary = RefineSummary();
  NRSFM_RETURN_IF_ERROR(options.Check());
  ProblemOptions problem_options;
  problem_options.constant_rotations = !options.refine_rotations;
  problem_options.constant_translations = !options.refine_translations;
  problem_options.constant_weights = !options.refine_weights;
  problem_options.constant_basis = !options.refine_basis;
  problem_options.constant_scales = !options.refine_scales;
  problem_options.robust_loss = options.robust_loss;
  problem_options.robust_scale = options.robust_scale;
  problem_options.constant_rig = !options.refine_rig;
  problem_options.smoothness_weight = options.smoothness_weight;
  problem_options.smoothness_edges.reference_frame = options.smoothness_reference_frame;
  problem_options.rigidity_weight = options.rigidity_weight;
  problem_options.temporal_weights_weight = options.temporal_weights_weight;
  problem_options.temporal_rotations_weight = options.temporal_rotations_weight;
  problem_options.temporal_shape_weight = options.temporal_shape_weight;
  problem_options.rotation_acceleration_weight = options.rotation_acceleration_weight;
  ProblemBuilder builder(&measurements, model);
  NRSFM_RETURN_IF_ERROR(
      builder.AddReprojectionTerms(problem_options).WithContext("refine"));
  ExtraTermCounts extra;
  NRSFM_RETURN_IF_ERROR(
      AddExtraTerms(problem_options, &builder, &extra).WithContext("refine"));
  const double build_seconds = SecondsSince(start);
  NRSFM_RETURN_IF_ERROR(SolveProblem(options, &builder, summary));
  summary->num_extra_residual_blocks = extra.smoothness + extra.rigidity +
                                       extra.temporal_weights +
                                       extra.temporal_rotations +
                                       extra.temporal_shape +
                                       extra.rotation_acceleration;
  summary->build_seconds += build_seconds;
  summary->seconds = SecondsSince(start);
  return Status::OK();
}

Status SolveProblem(const RefineOptions& options, ProblemBuilder* builder,
                    RefineSummary* summary) {
  CHECK(builder != nullptr);
  CHECK(summary != nullptr);
  const Clock::time_point start = Clock::now();
  *summary = RefineSummary();
  NRSFM_RETURN_IF_ERROR(options.Check());
  const Measurements& measurements = builder->measurements();
  Model* model = builder->model();
  const Model input = *model;
  summary->num_residual_blocks = builder->num_reprojection_terms();
  summary->initial_reprojection_rms = ReprojectionRms(measurements, *model);

  ceres::Solver::Options solver_options;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = options.function_tolerance;
  solver_options.gradient_tolerance = options.gradient_tolerance;
  solver_options.parameter_tolerance = options.parameter_tolerance;
  if (options.max_seconds > 0.0) {
    solver_options.max_solver_time_in_seconds = options.max_seconds;
  }
  solver_options.num_threads = options.num_threads;
  solver_options.initial_trust_region_radius = kInitialTrustRegionRadius;
  solver_options.logging_type = ceres::SILENT;
  solver_options.minimizer_progress_to_stdout = false;
  ProgressCallback callback(options);
  solver_options.callbacks.push_back(&callback);
  LinearSolverChoice used = LinearSolverChoice::kAuto;
  NRSFM_RETURN_IF_ERROR(ConfigureLinearSolver(options.linear_solver, builder,
                                              &solver_options, &used)
                            .WithContext("refine"));
  summary->linear_solver = LinearSolverName(used);
  std::string invalid;
  if (!solver_options.IsValid(&invalid)) {
    return Status::Error("refine: invalid Ceres options: " + invalid);
  }
  summary->build_seconds = SecondsSince(start);

  ceres::Solver::Summary ceres_summary;
  ceres::Solve(solver_options, builder->problem(), &ceres_summary);
  callback.ReportRemaining(ceres_summary);

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
  summary->ceres_report = ceres_summary.FullReport();
  summary->usable = ceres_summary.IsSolutionUsable();
  if (summary->usable && !model->Validate().ok()) {
    summary->usable = false;
    summary->message = "the refined model is not finite (" + summary->message + ")";
  }
  // Ceres calls a solve usable when its cost overflowed to Inf (residuals of
  // ~1e155 or more); such a model fits nothing.
  if (summary->usable &&
      !(std::isfinite(summary->final_cost) &&
        std::isfinite(ReprojectionRms(measurements, *model)))) {
    summary->usable = false;
    summary->message = "the cost or the reprojection error is not finite "
                       "(values too large?) (" + summary->message + ")";
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
