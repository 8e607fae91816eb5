#include "solvers/pipeline/prior_comparison.h"

#include <condition_variable>
#include <limits>
#include <mutex>
#include <utility>

#include "core/math/parallel_for.h"

namespace nrsfm {

Status RefineFullOrAlternative(const ProblemOptions& full,
                               const ProblemOptions& alternative,
                               const SolverOptions& solver, bool side_by_side,
                               double max_fit_ratio,
                               const Measurements& measurements, Model* model,
                               RefineSummary* summary,
                               PriorComparison* comparison) {
  *comparison = PriorComparison();
  // The lockstep: the full refinement publishes each iteration it reaches
  // and, when it ends, the iteration count the alternative may run (all of
  // them when it did not converge); the alternative, after each of its
  // iterations, waits until the full one has passed it or ended.
  constexpr int kUnbounded = std::numeric_limits<int>::max();
  std::mutex mutex;
  std::condition_variable changed;
  int full_iteration = -1, full_end = -1, alternative_iteration = 0;
  SolverOptions with = solver;
  with.progress = [&](const IterationReport& report) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      full_iteration = report.iteration;
    }
    changed.notify_all();
    if (solver.progress) solver.progress(report);
  };
  SolverOptions quiet = solver;
  quiet.progress = [&alternative_iteration](const IterationReport& report) {
    alternative_iteration = report.iteration;
  };
  quiet.stop_requested = [&] {
    std::unique_lock<std::mutex> lock(mutex);
    changed.wait(lock, [&] {
      return full_end >= 0 || full_iteration > alternative_iteration;
    });
    return full_end >= 0 && alternative_iteration >= full_end;
  };
  Model other = *model;
  RefineSummary other_summary;
  Status full_status, other_status;
  ParallelForWorker(
      2, side_by_side ? 2 : 1, /*grain=*/1, [&](int begin, int end, int) {
        for (int i = begin; i < end; ++i) {
          if (i == 0) {
            full_status = Refine(full, with, measurements, model, summary);
            {
              std::lock_guard<std::mutex> lock(mutex);
              full_end = full_status.ok() && summary->converged
                             ? summary->iterations
                             : kUnbounded;
            }
            changed.notify_all();
          } else {
            other_status = Refine(alternative, quiet, measurements, &other,
                                  &other_summary);
          }
        }
      });
  NRSFM_RETURN_IF_ERROR(full_status);
  if (summary->stopped || !other_status.ok() || !other_summary.usable) {
    return Status::OK();  // a stop asked for, or no fit to compare with
  }
  if (summary->usable && other_summary.reprojection_rms > 0.0) {
    comparison->fit_ratio =
        summary->reprojection_rms / other_summary.reprojection_rms;
  }
  if (summary->usable && comparison->fit_ratio <= max_fit_ratio) {
    return Status::OK();
  }
  comparison->kept_full = false;
  if (other_summary.stopped) {
    // Stopped by the lockstep: refined on to its end, the answer.
    RefineSummary rest;
    NRSFM_RETURN_IF_ERROR(
        Refine(alternative, solver, measurements, &other, &rest));
    if (rest.usable) {
      rest.initial_cost = other_summary.initial_cost;
      rest.initial_reprojection_rms = other_summary.initial_reprojection_rms;
      rest.iterations += other_summary.iterations;
      other_summary = rest;
    }
  }
  *model = std::move(other);
  *summary = other_summary;
  return Status::OK();
}

}  // namespace nrsfm
