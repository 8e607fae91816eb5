#include "solvers/pipeline/stages.h"

#include <algorithm>
#include <string>
#include <utility>

#include "core/math/parallel_for.h"
#include "problems/extra_terms.h"
#include "solvers/pipeline/prior_comparison.h"
#include "solvers/pipeline/two_starts.h"

namespace nrsfm {

Status StartAndRefine(const ReconstructOptions& options, StartMethod method,
                      const Measurements& measurements,
                      const PriorDecision& decision, double strength,
                      StartCache* cache, ReconstructResult* result,
                      KeptProblem* kept) {
  if (options.solver.stop_requested && options.solver.stop_requested()) {
    return Status::Error("stopped on request");
  }
  StartOptions start = options.start;
  start.method = method;
  // With priors = auto the path is measured on a start with at most
  // CameraBasesCap bases: with more, the start's rotations are not reliable
  // enough to tell. That start (the reference) is computed beside the
  // start itself when there are threads for both (each start is the same
  // for any thread count; inputs above kMaxObservationsForTwoAtOnce compute
  // them one after the other, as the two refinements).
  const int cap = CameraBasesCap(options.prior_rule, measurements);
  const bool with_reference =
      options.priors == PriorMode::kAuto &&
      decision.term_weights.count(kTemporalShapeTerm) > 0 &&
      start.num_bases > cap;
  StartOptions fewer = start;
  fewer.num_bases = cap;
  Model reference;
  StartSummary reference_summary;
  Status status, reference_status = Status::Error("not computed");
  const int threads = options.solver.num_threads;
  const bool beside = with_reference && threads >= 2 &&
                      measurements.NumVisible() <= kMaxObservationsForTwoAtOnce;
  const int reference_threads = beside ? threads / 2 : threads;
  ParallelForWorker(
      with_reference ? 2 : 1, beside ? 2 : 1, /*grain=*/1,
      [&](int begin, int end, int) {
        for (int i = begin; i < end; ++i) {
          if (i == 0) {
            status = ComputeStart(
                start, measurements, &result->model, &result->start,
                threads - (beside ? reference_threads : 0), cache);
          } else {
            reference_status =
                ComputeStart(fewer, measurements, &reference,
                             &reference_summary, reference_threads, cache);
          }
        }
      });
  NRSFM_RETURN_IF_ERROR(status);
  ProblemOptions problem = options.problem;
  result->priors = decision;
  if (options.priors == PriorMode::kAuto) {
    const Model* path =
        with_reference && reference_status.ok() ? &reference : &result->model;
    DecideStartPriors(options.prior_rule, result->model, *path, strength,
                      &result->priors);
    problem.term_weights = result->priors.term_weights;
  } else {
    result->priors.term_weights = problem.term_weights;
  }
  if (kept != nullptr) {
    return Refine(problem, options.solver, measurements, &result->model,
                  &result->refine, kept);
  }
  const double alternative = result->priors.temporal_shape_alternative;
  const auto temporal = problem.term_weights.find(kTemporalShapeTerm);
  const bool weaker = temporal != problem.term_weights.end() &&
                      alternative >= 0.0 && alternative < temporal->second;
  if (options.priors != PriorMode::kAuto ||
      (problem.term_weights.count(kRotationAccelerationTerm) == 0 && !weaker)) {
    return Refine(problem, options.solver, measurements, &result->model,
                  &result->refine);
  }
  // The full priors (temporal_shape at its full weight, the path prior when
  // a candidate) against the alternative (the coherence weight, no path
  // prior), side by side but for inputs above kMaxObservationsForTwoAtOnce
  // (the two problems would not both fit in memory).
  ProblemOptions weaker_problem = problem;
  weaker_problem.term_weights.erase(kRotationAccelerationTerm);
  if (weaker) weaker_problem.term_weights[kTemporalShapeTerm] = alternative;
  const bool side_by_side =
      threads >= 2 && measurements.NumVisible() <= kMaxObservationsForTwoAtOnce;
  PriorComparison comparison;
  NRSFM_RETURN_IF_ERROR(RefineFullOrAlternative(
      problem, weaker_problem, options.solver, side_by_side,
      options.prior_rule.max_prior_fit_ratio, measurements, &result->model,
      &result->refine, &comparison));
  result->priors.prior_fit_ratio = comparison.fit_ratio;
  if (!comparison.kept_full) {
    result->priors.term_weights = weaker_problem.term_weights;
  }
  return Status::OK();
}

namespace {

// The factorization and the rigid start, each refined (StartAndRefine),
// side by side in lockstep with the rule of solvers/pipeline/two_starts.h that
// abandons one that falls behind: at once with num_threads ≥ 2 (each on
// num_threads / 2 threads), in turns with one. Inputs of more than
// kMaxObservationsForTwoAtOnce observations, whose two problems would not
// both fit in memory, refine one start after the other on every thread,
// the second abandoned by the same rule once the first has converged; the
// second then refines in the first's problem when it is the same (no extra
// term: KeptProblem).
void RefineBothStarts(const ReconstructOptions& options,
                      const Measurements& measurements,
                      const PriorDecision& decision, double strength,
                      StartCache* cache, ReconstructResult* factorization,
                      Status* factorization_status, ReconstructResult* rigid,
                      Status* rigid_status) {
  if (measurements.NumVisible() > kMaxObservationsForTwoAtOnce) {
    KeptProblem kept;
    *factorization_status =
        StartAndRefine(options, StartMethod::kFactorization, measurements,
                       decision, strength, cache, factorization, &kept);
    // The rule of solvers/pipeline/two_starts.h with the first refinement
    // ended: the second is abandoned once it has run RaceIterations(n)
    // iterations without reaching the first's cost.
    const RefineSummary& first = factorization->refine;
    const bool race =
        factorization_status->ok() && first.converged && first.usable;
    ReconstructOptions second = options;
    int iteration = -1;
    double cost = 0.0;
    second.solver.progress = [&options, &iteration,
                              &cost](const IterationReport& report) {
      iteration = report.iteration;
      cost = report.cost;
      if (options.solver.progress) options.solver.progress(report);
    };
    second.solver.stop_requested = [&options, &iteration, &cost, &first, race] {
      if (options.solver.stop_requested && options.solver.stop_requested()) {
        return true;
      }
      return race && iteration >= RaceIterations(first.iterations) &&
             cost >= first.final_cost;
    };
    *rigid_status = StartAndRefine(second, StartMethod::kRigid, measurements,
                                   decision, strength, cache, rigid, &kept);
    return;
  }
  const auto lane = [&options, &measurements, &decision, strength, cache](
                        StartMethod method, ReconstructResult* result,
                        Status* status) -> RaceRefinement {
    return [&options, &measurements, &decision, strength, cache, method, result,
            status](const SolverOptions& solver) {
      ReconstructOptions own = options;
      own.solver = solver;
      *status = StartAndRefine(own, method, measurements, decision, strength,
                               cache, result, /*kept=*/nullptr);
      RaceOutcome outcome;
      if (!status->ok()) return outcome;
      outcome.converged = result->refine.converged;
      outcome.usable = result->refine.usable;
      outcome.final_cost = result->refine.final_cost;
      outcome.iterations = result->refine.iterations;
      return outcome;
    };
  };
  SolverOptions each = options.solver;
  each.num_threads = std::max(1, options.solver.num_threads / 2);
  RunTwoRefinements(
      each, /*concurrent=*/options.solver.num_threads >= 2,
      lane(StartMethod::kFactorization, factorization, factorization_status),
      lane(StartMethod::kRigid, rigid, rigid_status));
}

// Whether refined result `a` is better than `b`: a usable solution beats an
// unusable one; then the lower final cost wins.
bool IsBetter(const ReconstructResult& a, const ReconstructResult& b) {
  if (a.refine.usable != b.refine.usable) return a.refine.usable;
  return a.refine.final_cost < b.refine.final_cost;
}

// The shape stage after the camera stage: the camera stage's model (reduced
// to K bases when it has more), refined with its rotations held
// and the same shape prior (the path prior has nothing left to act on).
// result->camera_refine keeps the camera stage's summary; result->refine
// becomes the shape stage's, result->model its model (the reduced model when
// that refinement is not usable).
Status RefineWithCameraHeld(const ReconstructOptions& options,
                            const Measurements& measurements,
                            ReconstructResult* result) {
  result->camera_stage = true;
  result->camera_refine = result->refine;
  if (!result->camera_refine.usable) {
    return Status::Error("the camera stage (" +
                         std::to_string(result->model.num_bases) +
                         " bases) did not give a usable solution: " +
                         result->camera_refine.message);
  }
  if (options.solver.stop_requested && options.solver.stop_requested()) {
    return Status::Error("stopped on request");
  }
  if (result->model.num_bases > options.start.num_bases) {
    result->model = ReduceNumBases(result->model, options.start.num_bases);
  }
  ProblemOptions problem = options.problem;
  problem.term_weights = result->priors.term_weights;
  problem.term_weights.erase(kRotationAccelerationTerm);
  problem.constant_rotations = true;
  result->refine = RefineSummary();
  return Refine(problem, options.solver, measurements, &result->model,
                &result->refine);
}

}  // namespace

Status SolveWithPriors(const ReconstructOptions& options,
                       const Measurements& measurements,
                       const PriorDecision& rule, double strength,
                       StartCache* cache, ReconstructResult* result) {
  const int num_bases = options.start.num_bases;
  PriorDecision decision = rule;
  if (strength > 1.0 && decision.term_weights.count(kTemporalShapeTerm) == 0 &&
      decision.term_weights.count(kDeformationTerm) == 0) {
    // Exact low-rank tracks whose answer still was not determined: the
    // shape prior the rule would add for noisy tracks.
    if (decision.video) {
      decision.term_weights[kTemporalShapeTerm] =
          options.prior_rule.temporal_shape_weight;
    } else {
      decision.term_weights[kDeformationTerm] =
          options.prior_rule.deformation_weight;
    }
  }
  // The camera stage: the start and its refinement with K_cam ≥ K bases
  // (K_cam = K with priors = manual).
  ReconstructOptions camera = options;
  const bool shape_prior =
      decision.term_weights.count(kTemporalShapeTerm) > 0 ||
      decision.term_weights.count(kDeformationTerm) > 0;
  if (shape_prior) {
    camera.start.num_bases = std::max(num_bases, decision.camera_num_bases);
    camera.solver.function_tolerance =
        std::max(options.solver.function_tolerance,
                 options.prior_rule.camera_function_tolerance);
  }
  if (options.start.method != StartMethod::kAuto) {
    NRSFM_RETURN_IF_ERROR(StartAndRefine(camera, options.start.method,
                                         measurements, decision, strength,
                                         cache, result, /*kept=*/nullptr));
  } else if (decision.term_weights.count(kTemporalShapeTerm) > 0) {
    NRSFM_RETURN_IF_ERROR(StartAndRefine(camera, StartMethod::kTriple,
                                         measurements, decision, strength,
                                         cache, result, /*kept=*/nullptr));
  } else {
    // Both starts are refined and the lower refined cost is kept: a start's
    // own reprojection error does not tell which basin it is in (the rigid
    // start can fit the tracks better than the factorisation start and still
    // converge to a depth-degenerate solution).
    ReconstructResult factorization, rigid;
    Status factorization_status, rigid_status;
    RefineBothStarts(camera, measurements, decision, strength, cache,
                     &factorization, &factorization_status, &rigid,
                     &rigid_status);
    if (!factorization_status.ok() && !rigid_status.ok()) {
      return Status::Error("both starts failed: factorization: " +
                           factorization_status.message() +
                           "; rigid: " + rigid_status.message());
    }
    const bool keep_rigid =
        !factorization_status.ok() ||
        (rigid_status.ok() && IsBetter(rigid, factorization));
    *result = keep_rigid ? std::move(rigid) : std::move(factorization);
    const Status& other = keep_rigid ? factorization_status : rigid_status;
    if (!other.ok()) {
      result->start.warnings.push_back(
          std::string(keep_rigid ? "factorization" : "rigid") +
          " start failed: " + other.message());
    }
  }
  // The shape stage when the camera stage had more bases: its shapes reduced
  // to K bases (ReduceNumBases), refined with its rotations held. With
  // K_cam = K the camera stage's result is the answer: a shape stage would
  // re-solve the same problem with the rotations held from its end, and only
  // polish it (measured in docs/performance.md: no gain in e3D over the
  // generalisation protocol, up to 12× the LM steps on noisy tracks).
  if (shape_prior && result->model.num_bases > num_bases) {
    NRSFM_RETURN_IF_ERROR(RefineWithCameraHeld(options, measurements, result));
  }
  return Status::OK();
}

}  // namespace nrsfm
