#include "solvers/refine/refine.h"

#include <ceres/iteration_callback.h>
#include <ceres/solver.h>
#include <glog/logging.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "core/eval/metrics.h"
#include "problems/extra_terms.h"
#include "solvers/refine/minimizer_choice.h"
#include "solvers/refine/structured_layout.h"
#include "solvers/refine/structured_solver.h"

namespace nrsfm {

StructuredLayout MakeStructuredLayout(ProblemBuilder* builder) {
  const Model& model = *builder->model();
  StructuredLayout layout;
  layout.groups.resize(model.num_frames);
  for (int t = 0; t < model.num_frames; ++t) {
    std::vector<double*>& group = layout.groups[t];
    for (int c = 0; c < model.num_cameras; ++c) {
      group.push_back(builder->RotationBlock(t, c));
      group.push_back(builder->TranslationBlock(t, c));
      if (c > 0) group.push_back(builder->ScaleBlock(t, c));
      group.push_back(builder->DepthBlock(t, c));
    }
    group.push_back(builder->WeightsBlock(t));
  }
  for (int c = 1; c < model.num_cameras; ++c) {
    layout.globals.push_back(builder->RigRotationBlock(c));
    layout.globals.push_back(builder->RigScaleBlock(c));
  }
  layout.eliminated = builder->PointBlocks();
  return layout;
}

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
    if (options_.stop_requested && options_.stop_requested()) {
      stopped_ = true;
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    return ceres::SOLVER_CONTINUE;
  }

  // Whether stop_requested ended the solve.
  bool stopped() const { return stopped_; }

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
              << report.cost
              << (summary.step_is_successful ? "" : " (rejected)")
              << " linear solver iterations "
              << summary.linear_solver_iterations << " time " << report.seconds
              << " s";
    }
    if (options_.progress) options_.progress(report);
  }

  const SolverOptions& options_;
  int last_reported_ = -1;
  bool stopped_ = false;
};

// Runs the structured solver; false when the layout does not fit the
// problem (`error` says why).
bool SolveWithStructuredSolver(const SolverOptions& options,
                               ProblemBuilder* builder, RefineSummary* summary,
                               std::string* error,
                               structured::StructuredBlocks* kept) {
  StructuredSolverOptions structured;
  structured.solver = options;
  structured.solver.progress = [&options](const IterationReport& report) {
    if (options.verbosity >= 1) {
      VLOG(1) << "refine: iteration " << report.iteration << " cost "
              << report.cost << " time " << report.seconds << " s";
    }
    if (options.progress) options.progress(report);
  };
  StructuredSolverSummary result;
  const bool solved =
      kept != nullptr
          ? SolveStructured(structured, MakeStructuredLayout(builder),
                            builder->problem(), &result, error, kept)
          : SolveStructured(structured, MakeStructuredLayout(builder),
                            builder->problem(), &result, error);
  if (!solved) return false;
  summary->message = result.message;
  summary->converged = result.converged;
  summary->stopped = result.stopped;
  summary->initial_cost = result.initial_cost;
  summary->final_cost = result.final_cost;
  summary->iterations = result.iterations;
  summary->residual_seconds = result.evaluate_seconds;
  summary->linear_solver_seconds =
      result.preconditioner_seconds + result.cg_seconds;
  summary->minimizer_seconds = result.total_seconds;
  summary->usable = result.usable;
  std::ostringstream report;
  report << "structured Levenberg-Marquardt: " << result.iterations
         << " iterations, " << result.cg_iterations
         << " conjugate-gradient iterations, cost " << result.initial_cost
         << " -> " << result.final_cost << ", " << result.message << ", "
         << result.total_seconds << " s (evaluation " << result.evaluate_seconds
         << " s, preconditioner " << result.preconditioner_seconds
         << " s, conjugate gradients " << result.cg_seconds
         << " s; set-up before it " << result.setup_seconds << " s)";
  summary->ceres_report = report.str();
  VLOG(1) << "refine: " << summary->ceres_report;
  return true;
}

// Runs Ceres' own minimiser with `linear_solver` (not kAuto or kStructured);
// build_seconds is the time since `start` when the solver is configured.
Status SolveWithCeres(const SolverOptions& options,
                      LinearSolverChoice linear_solver, Clock::time_point start,
                      ProblemBuilder* builder, RefineSummary* summary) {
  ProgressCallback callback(options);
  ceres::Solver::Summary ceres_summary;
  NRSFM_RETURN_IF_ERROR(
      SolveCeres(
          options,
          [&](ceres::Solver::Options* solver_options) {
            solver_options->callbacks.push_back(&callback);
            LinearSolverChoice used = LinearSolverChoice::kAuto;
            NRSFM_RETURN_IF_ERROR(ConfigureLinearSolver(linear_solver, builder,
                                                        solver_options, &used));
            summary->linear_solver = LinearSolverName(used);
            summary->build_seconds = SecondsSince(start);
            return Status::OK();
          },
          builder->problem(), &ceres_summary)
          .WithContext("refine"));
  callback.ReportRemaining(ceres_summary);

  summary->stopped = callback.stopped();
  summary->message = summary->stopped ? std::string("stopped on request")
                                      : ceres_summary.message;
  summary->converged = ceres_summary.termination_type == ceres::CONVERGENCE;
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
  return Status::OK();
}

}  // namespace

namespace {

// Whether `options` has no extra term (AddExtraTerms then adds nothing and
// changes nothing).
bool NoExtraTerm(const ProblemOptions& options) {
  for (const auto& term : options.term_weights) {
    if (term.second != 0.0) return false;
  }
  return true;
}

// Whether the data term of `a` and `b` is built the same way.
bool SameDataTerm(const ProblemOptions& a, const ProblemOptions& b) {
  const Eigen::ArrayXXd& wa = a.observation_weights;
  const Eigen::ArrayXXd& wb = b.observation_weights;
  return a.constant_rotations == b.constant_rotations &&
         a.constant_translations == b.constant_translations &&
         a.constant_weights == b.constant_weights &&
         a.constant_basis == b.constant_basis &&
         a.constant_scales == b.constant_scales &&
         a.constant_rig == b.constant_rig && a.robust_loss == b.robust_loss &&
         a.robust_scale == b.robust_scale && wa.rows() == wb.rows() &&
         wa.cols() == wb.cols() && (wa.size() == 0 || (wa == wb).all());
}

// The same tracks, bit for bit.
bool SameMeasurements(const Measurements& a, const Measurements& b) {
  return a.num_frames == b.num_frames && a.num_cameras == b.num_cameras &&
         a.num_points == b.num_points && a.W.rows() == b.W.rows() &&
         a.W.cols() == b.W.cols() && a.visible.rows() == b.visible.rows() &&
         a.visible.cols() == b.visible.cols() &&
         std::memcmp(a.W.data(), b.W.data(), sizeof(double) * a.W.size()) ==
             0 &&
         (a.visible.array() == b.visible.array()).all();
}

bool SameSizes(const Model& a, const Model& b) {
  const auto same = [](const auto& x, const auto& y) {
    return x.rows() == y.rows() && x.cols() == y.cols();
  };
  return a.num_frames == b.num_frames && a.num_cameras == b.num_cameras &&
         a.num_points == b.num_points && a.num_bases == b.num_bases &&
         same(a.rotations, b.rotations) &&
         same(a.translations, b.translations) && same(a.weights, b.weights) &&
         same(a.basis, b.basis) && same(a.scales, b.scales) &&
         same(a.rig_rotations, b.rig_rotations) &&
         same(a.rig_scales, b.rig_scales);
}

}  // namespace

struct KeptProblem::State {
  // Copies of the caller's: the builder's data and the blocks' values.
  Measurements measurements;
  Model storage;
  ProblemOptions options;
  std::unique_ptr<ProblemBuilder> builder;
  // The minimiser chosen for it and the structured solver's layout.
  bool chosen = false;
  MinimizerOption requested_minimizer = MinimizerOption::kAuto;
  LinearSolverChoice requested = LinearSolverChoice::kAuto;
  MinimizerChoice choice;
  structured::StructuredBlocks blocks;

  bool Fits(const ProblemOptions& problem, const Measurements& m,
            const Model& model) const {
    return NoExtraTerm(problem) && SameDataTerm(problem, options) &&
           SameSizes(model, storage) && SameMeasurements(m, measurements);
  }
};

KeptProblem::KeptProblem() = default;
KeptProblem::~KeptProblem() = default;
KeptProblem::KeptProblem(KeptProblem&&) noexcept = default;
KeptProblem& KeptProblem::operator=(KeptProblem&&) noexcept = default;

namespace {

// SolveProblem() with the minimiser's choice and the structured layout kept
// in `state` (null: none kept).
Status SolveProblemWith(const SolverOptions& caller, ProblemBuilder* builder,
                        RefineSummary* summary, KeptProblem::State* state);

}  // namespace

Status Refine(const ProblemOptions& problem, const SolverOptions& solver,
              const Measurements& measurements, Model* model,
              RefineSummary* summary, KeptProblem* kept) {
  CHECK(model != nullptr);
  CHECK(summary != nullptr);
  CHECK(kept != nullptr);
  if (!NoExtraTerm(problem)) {
    // Never reused (the terms' build may depend on the model): not kept.
    kept->state_.reset();
    return Refine(problem, solver, measurements, model, summary);
  }
  const Clock::time_point start = Clock::now();
  *summary = RefineSummary();
  NRSFM_RETURN_IF_ERROR(solver.Check().WithContext("refine"));
  KeptProblem::State* state = kept->state_.get();
  const bool reuse =
      state != nullptr && state->Fits(problem, measurements, *model);
  if (reuse) {
    NRSFM_RETURN_IF_ERROR(
        ProblemBuilder::CheckInputs(problem, measurements, *model)
            .WithContext("refine"));
    state->storage = *model;  // the same sizes: the blocks' storage stays
    ++kept->reuses_;
  } else {
    kept->state_.reset();  // freed before the new one is built
    auto fresh = std::make_unique<KeptProblem::State>();
    fresh->measurements = measurements;
    fresh->storage = *model;
    fresh->options = problem;
    fresh->builder =
        std::make_unique<ProblemBuilder>(&fresh->measurements, &fresh->storage);
    NRSFM_RETURN_IF_ERROR(
        fresh->builder->AddReprojectionTerms(problem).WithContext("refine"));
    NRSFM_RETURN_IF_ERROR(
        AddExtraTerms(problem, fresh->builder.get()).WithContext("refine"));
    kept->state_ = std::move(fresh);
    state = kept->state_.get();
  }
  const double build_seconds = SecondsSince(start);
  NRSFM_RETURN_IF_ERROR(
      SolveProblemWith(solver, state->builder.get(), summary, state));
  *model = state->storage;
  summary->build_seconds += build_seconds;
  VLOG(1) << "refine: problem "
          << (reuse ? "kept from the last, values set" : "built") << " in "
          << build_seconds << " s, solved in "
          << SecondsSince(start) - build_seconds << " s";
  summary->seconds = SecondsSince(start);
  return Status::OK();
}

Status Refine(const ProblemOptions& problem, const SolverOptions& solver,
              const Measurements& measurements, Model* model,
              RefineSummary* summary) {
  CHECK(model != nullptr);
  CHECK(summary != nullptr);
  const Clock::time_point start = Clock::now();
  *summary = RefineSummary();
  NRSFM_RETURN_IF_ERROR(solver.Check().WithContext("refine"));
  ProblemBuilder builder(&measurements, model);
  NRSFM_RETURN_IF_ERROR(
      builder.AddReprojectionTerms(problem).WithContext("refine"));
  NRSFM_RETURN_IF_ERROR(AddExtraTerms(problem, &builder).WithContext("refine"));
  const double build_seconds = SecondsSince(start);
  NRSFM_RETURN_IF_ERROR(SolveProblem(solver, &builder, summary));
  summary->build_seconds += build_seconds;
  VLOG(1) << "refine: problem built in " << build_seconds << " s, solved in "
          << SecondsSince(start) - build_seconds << " s";
  summary->seconds = SecondsSince(start);
  return Status::OK();
}

Status SolveProblem(const SolverOptions& caller, ProblemBuilder* builder,
                    RefineSummary* summary) {
  return SolveProblemWith(caller, builder, summary, nullptr);
}

namespace {

Status SolveProblemWith(const SolverOptions& caller, ProblemBuilder* builder,
                        RefineSummary* summary, KeptProblem::State* state) {
  CHECK(builder != nullptr);
  CHECK(summary != nullptr);
  const Clock::time_point start = Clock::now();
  *summary = RefineSummary();
  // The caller's callbacks, timed (RefineSummary::callback_seconds).
  double callback_seconds = 0.0;
  SolverOptions options = caller;
  if (caller.progress) {
    options.progress = [&caller,
                        &callback_seconds](const IterationReport& report) {
      const Clock::time_point begin = Clock::now();
      caller.progress(report);
      callback_seconds += SecondsSince(begin);
    };
  }
  if (caller.stop_requested) {
    options.stop_requested = [&caller, &callback_seconds] {
      const Clock::time_point begin = Clock::now();
      const bool stop = caller.stop_requested();
      callback_seconds += SecondsSince(begin);
      return stop;
    };
  }
  NRSFM_RETURN_IF_ERROR(options.Check().WithContext("refine"));
  const Measurements& measurements = builder->measurements();
  Model* model = builder->model();
  const Model input = *model;
  summary->num_residual_blocks = builder->num_reprojection_terms();
  summary->initial_reprojection_rms =
      ReprojectionRms(measurements, *model, options.num_threads);

  // A kept problem is the same problem: its choice is kept with it (the
  // solver options that decide it, minimizer and linear_solver, are
  // compared).
  if (state != nullptr &&
      !(state->chosen && state->requested_minimizer == options.minimizer &&
        state->requested == options.linear_solver)) {
    state->choice =
        ChooseMinimizer(options.minimizer, options.linear_solver, builder);
    state->requested_minimizer = options.minimizer;
    state->requested = options.linear_solver;
    state->chosen = true;
    state->blocks = structured::StructuredBlocks();
  }
  const MinimizerChoice choice =
      state != nullptr
          ? state->choice
          : ChooseMinimizer(options.minimizer, options.linear_solver, builder);
  bool solved = false;
  if (choice.minimizer == Minimizer::kStructured) {
    std::string error;
    summary->linear_solver = LinearSolverName(LinearSolverChoice::kStructured);
    summary->build_seconds = SecondsSince(start);
    solved =
        SolveWithStructuredSolver(options, builder, summary, &error,
                                  state != nullptr ? &state->blocks : nullptr);
    if (!solved && !choice.fallback) {
      return Status::Error("refine: linear solver structured: " + error);
    }
    // Otherwise chosen by auto for a problem it does not fit (a term the
    // caller added that couples two points): Ceres' own solver runs instead.
  }
  if (!solved) {
    NRSFM_RETURN_IF_ERROR(SolveWithCeres(options, choice.ceres_linear_solver,
                                         start, builder, summary));
  }
  if (summary->usable && !model->Validate().ok()) {
    summary->usable = false;
    summary->message =
        "the refined model is not finite (" + summary->message + ")";
  }
  // Ceres calls a solve usable when its cost overflowed to Inf (residuals of
  // ~1e155 or more); such a model fits nothing.
  summary->reprojection_rms =
      ReprojectionRms(measurements, *model, options.num_threads);
  if (summary->usable && !(std::isfinite(summary->final_cost) &&
                           std::isfinite(summary->reprojection_rms))) {
    summary->usable = false;
    summary->message =
        "the cost or the reprojection error is not finite "
        "(values too large?) (" +
        summary->message + ")";
  }
  if (!summary->usable) {
    *model = input;
    summary->final_cost = summary->initial_cost;
    summary->reprojection_rms = summary->initial_reprojection_rms;
  }
  summary->callback_seconds = callback_seconds;
  summary->seconds = SecondsSince(start);
  return Status::OK();
}

}  // namespace

}  // namespace nrsfm
