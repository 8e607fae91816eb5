#include "solvers/refine.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <ceres/iteration_callback.h>
#include <ceres/solver.h>
#include <glog/logging.h>

#include "core/metrics.h"
#include "problems/extra_terms.h"

namespace nrsfm {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Forwards every LM iteration to the user's callback and to VLOG(1).
class ProgressCallback : public ceres::IterationCallback {
 public:
  explicit ProgressCallback(const SolverOptions& options) : options_(options) {}

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

  const SolverOptions& options_;
  int last_reported_ = -1;
};

}  // namespace

Status Refine(const ProblemOptions& problem, const SolverOptions& solver,
              const Measurements& measurements, Model* model,
              RefineSummary* summary) {
  CHECK(model != nullptr);
  CHECK(summary != nullptr);
  const Clock::time_point start = Clock::now();
  *summary = RefineSummary();
  NRSFM_RETURN_IF_ERROR(solver.Check().WithContext("refine"));
  ProblemBuilder builder(&measurements, model);
  NRSFM_RETURN_IF_ERROR(builder.AddReprojectionTerms(problem).WithContext("refine"));
  NRSFM_RETURN_IF_ERROR(AddExtraTerms(problem, &builder).WithContext("refine"));
  const double build_seconds = SecondsSince(start);
  NRSFM_RETURN_IF_ERROR(SolveProblem(solver, &builder, summary));
  summary->build_seconds += build_seconds;
  summary->seconds = SecondsSince(start);
  return Status::OK();
}

Status SolveProblem(const SolverOptions& options, ProblemBuilder* builder,
                    RefineSummary* summary) {
  CHECK(builder != nullptr);
  CHECK(summary != nullptr);
  const Clock::time_point start = Clock::now();
  *summary = RefineSummary();
  NRSFM_RETURN_IF_ERROR(options.Check().WithContext("refine"));
  const Measurements& measurements = builder->measurements();
  Model* model = builder->model();
  const Model input = *model;
  summary->num_residual_blocks = builder->num_reprojection_terms();
  summary->initial_reprojection_rms = ReprojectionRms(measurements, *model);

  ceres::Solver::Options solver_options = ToCeresOptions(options);
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
