#include "solvers/pipeline/reconstruct.h"

#include <glog/logging.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>

#include "core/enum_names.h"
#include "core/option_checker.h"
#include "core/parallel_for.h"
#include "problems/extra_terms.h"
#include "solvers/pipeline/drop_unobserved.h"
#include "solvers/pipeline/two_starts.h"

namespace nrsfm {
namespace {

constexpr EnumName<PriorMode> kPriorModeNames[] = {
    {PriorMode::kAuto, "auto"},
    {PriorMode::kManual, "manual"},
};

}  // namespace

const char* PriorModeName(PriorMode mode) {
  return NameOf(kPriorModeNames, mode);
}

Status ParsePriorMode(const std::string& name, PriorMode* mode) {
  return ParseName(kPriorModeNames, name, "prior mode", mode);
}

Status ReconstructOptions::Check() const {
  OptionChecker check("reconstruct");
  check.Nested(start.Check());
  check.Nested(problem.Check());
  check.Nested(solver.Check());
  check.Nested(prior_rule.Check());
  bool any_weight = false;
  for (const auto& [name, weight] : problem.term_weights)
    any_weight |= weight != 0.0;
  check.Require(priors == PriorMode::kManual || !any_weight,
                "term weights are given but priors = auto chooses them; set "
                "priors = manual to use your own");
  return check.status();
}

namespace {

// One start followed by its refinement. With priors = auto the start's
// camera path decides the path prior (`decision` holds the rule's other facts).
// `cache` holds the work the starts share (solvers/start/start.h); `kept`,
// when not null, the refinement's problem for the next start's
// (solvers/refine/refine.h, KeptProblem).
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
  // prior): refined side by side when there are threads for both (the
  // alternative reports no progress and asks for no stop of the caller's);
  // the full priors are kept when the tracks are fitted within
  // max_prior_fit_ratio with them. The alternative stops once it has run as
  // many iterations as the full priors took to converge (its fit then is no
  // better than at its end, so the test leans to the full priors), and goes
  // on to its end only when it is the answer.
  ProblemOptions free_path = problem;
  free_path.term_weights.erase(kRotationAccelerationTerm);
  if (weaker) free_path.term_weights[kTemporalShapeTerm] = alternative;
  std::atomic<int> with_iterations{-1};  // set once the one with it ends
  SolverOptions quiet = options.solver;
  int free_iteration = 0;
  quiet.progress = [&free_iteration](const IterationReport& report) {
    free_iteration = report.iteration;
  };
  quiet.stop_requested = [&free_iteration, &with_iterations] {
    const int n = with_iterations.load();
    return n >= 0 && free_iteration >= n;
  };
  Model free_model = result->model;
  RefineSummary free_summary;
  Status with_status, free_status;
  // Inputs above kMaxObservationsForTwoAtOnce refine one after the other
  // (the two problems would not both fit in memory).
  const bool side_by_side =
      threads >= 2 && measurements.NumVisible() <= kMaxObservationsForTwoAtOnce;
  ParallelForWorker(
      2, side_by_side ? 2 : 1, /*grain=*/1, [&](int begin, int end, int) {
        for (int i = begin; i < end; ++i) {
          if (i == 0) {
            with_status = Refine(problem, options.solver, measurements,
                                 &result->model, &result->refine);
            with_iterations.store(with_status.ok() && result->refine.converged
                                      ? result->refine.iterations
                                      : std::numeric_limits<int>::max() / 4);
          } else {
            free_status = Refine(free_path, quiet, measurements, &free_model,
                                 &free_summary);
          }
        }
      });
  NRSFM_RETURN_IF_ERROR(with_status);
  if (result->refine.stopped || !free_status.ok() || !free_summary.usable) {
    return Status::OK();  // a stop asked for, or no fit to compare with
  }
  if (result->refine.usable && free_summary.reprojection_rms > 0.0) {
    result->priors.prior_fit_ratio =
        result->refine.reprojection_rms / free_summary.reprojection_rms;
  }
  if (!result->refine.usable ||
      result->priors.prior_fit_ratio > options.prior_rule.max_prior_fit_ratio) {
    result->priors.term_weights = free_path.term_weights;
    if (free_summary.stopped) {
      // Abandoned by the race rule: refined on to its end, the answer.
      RefineSummary rest;
      NRSFM_RETURN_IF_ERROR(
          Refine(free_path, options.solver, measurements, &free_model, &rest));
      if (rest.usable) {
        rest.initial_cost = free_summary.initial_cost;
        rest.initial_reprojection_rms = free_summary.initial_reprojection_rms;
        rest.iterations += free_summary.iterations;
        free_summary = rest;
      }
    }
    result->model = std::move(free_model);
    result->refine = free_summary;
  }
  return Status::OK();
}

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

// The camera stage and, with K_cam > K, the shape stage, with the rule's
// decision `rule` (priors = auto) or the caller's terms; `strength`
// multiplies the shape prior (DecideStartPriors) and, above 1, adds it when
// the rule had none.
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

}  // namespace

double DepthRatio(const Model& model) {
  double depth = 0.0, plane = 0.0;
  for (int t = 0; t < model.num_frames; ++t) {
    const Eigen::Matrix3Xd x = model.ShapeInCamera(t, 0);
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    int n = 0;
    for (int p = 0; p < model.num_points; ++p) {
      if (!x.col(p).allFinite()) continue;
      centroid += x.col(p);
      ++n;
    }
    if (n == 0) continue;
    centroid /= n;
    for (int p = 0; p < model.num_points; ++p) {
      if (!x.col(p).allFinite()) continue;
      const Eigen::Vector3d d = x.col(p) - centroid;
      depth += d.z() * d.z();
      plane += 0.5 * (d.x() * d.x() + d.y() * d.y());
    }
  }
  return plane > 0.0 ? std::sqrt(depth / plane) : 0.0;
}

namespace {

// Whether a refinement of `options` ended at its iteration limit.
bool AtIterationLimit(const ReconstructOptions& options,
                      const RefineSummary& summary) {
  return summary.usable && !summary.converged && !summary.stopped &&
         summary.iterations >= options.solver.max_iterations;
}

// What the tool can see of a result without a ground truth, against its own
// rigid answer: usable, ended by a tolerance, no deeper than the rigid
// answer (or kLargeDepthRatio, whichever is larger) and fitting the tracks
// no worse. Empty when it passes, else the first reason it does not.
std::string WhyNotDetermined(const ReconstructOptions& options,
                             const ReconstructResult& result,
                             const ReconstructResult& rigid) {
  if (!result.refine.usable) return "the refinement was not usable";
  if (AtIterationLimit(options, result.refine) ||
      (result.camera_stage &&
       AtIterationLimit(options, result.camera_refine))) {
    return "the refinement stopped at its iteration limit";
  }
  const double depth = DepthRatio(result.model);
  const double rigid_depth = rigid.refine.usable ? DepthRatio(rigid.model) : 0;
  if (depth > std::max(kLargeDepthRatio, rigid_depth)) {
    std::ostringstream why;
    why << std::fixed << std::setprecision(1) << "its depth is " << depth
        << " times its image extent (the rigid answer's "
        << std::setprecision(2) << rigid_depth << ")";
    return why.str();
  }
  if (rigid.refine.usable &&
      result.refine.reprojection_rms > rigid.refine.reprojection_rms) {
    return "it fits the tracks worse than the rigid answer";
  }
  return "";
}

// The rigid answer (K = 1, the rigid start, no extra term) written with
// `num_bases` bases: the rigid shape as the first, the others zero.
Model RigidWithBases(const Model& rigid, int num_bases) {
  Model model = rigid;
  model.num_bases = num_bases;
  model.weights = Eigen::MatrixXd::Zero(num_bases, rigid.num_frames);
  model.weights.row(0) = rigid.weights.row(0);
  model.basis = Eigen::MatrixXd::Zero(3 * num_bases, rigid.num_points);
  model.basis.topRows(3) = rigid.basis.topRows(3);
  return model;
}

// The repair of a result the data did not determine (WhyNotDetermined,
// against the rigid answer computed here): re-solved with the shape prior
// kRepairStrengths times stronger, the first that passes kept; when none
// does, the rigid answer itself. result->repair says which.
Status Repair(const ReconstructOptions& options,
              const Measurements& measurements, const PriorDecision& rule,
              StartCache* cache, ReconstructResult* result) {
  if (result->refine.stopped ||
      (options.solver.stop_requested && options.solver.stop_requested())) {
    return Status::OK();  // the caller asked to stop: no further solve
  }
  // The rigid answer is computed only for a result that is not usable, ended
  // at its iteration limit or is deeper than kLargeDepthRatio: every other
  // passes the check against any rigid answer but by its fit, which a
  // refinement from a start with K ≥ 1 bases does not lose.
  if (result->refine.usable && !AtIterationLimit(options, result->refine) &&
      !(result->camera_stage &&
        AtIterationLimit(options, result->camera_refine)) &&
      DepthRatio(result->model) <= kLargeDepthRatio) {
    return Status::OK();
  }
  ReconstructOptions rigid_options = options;
  rigid_options.start.num_bases = 1;
  rigid_options.priors = PriorMode::kManual;
  rigid_options.problem.term_weights.clear();
  rigid_options.solver.progress = nullptr;  // reports are of the answer's
  ReconstructResult rigid;
  const Status rigid_status =
      StartAndRefine(rigid_options, StartMethod::kRigid, measurements,
                     PriorDecision(), 1.0, cache, &rigid, /*kept=*/nullptr);
  if (rigid_status.ok() && rigid.refine.usable) {
    result->rigid_reprojection_rms = rigid.refine.reprojection_rms;
    result->rigid_depth_ratio = DepthRatio(rigid.model);
  }
  std::string why = WhyNotDetermined(options, *result, rigid);
  if (why.empty()) return Status::OK();
  for (const double strength : kRepairStrengths) {
    if (options.solver.stop_requested && options.solver.stop_requested()) {
      return Status::Error("stopped on request");
    }
    ReconstructResult again;
    const Status status =
        SolveWithPriors(options, measurements, rule, strength, cache, &again);
    if (!status.ok()) continue;
    const std::string still = WhyNotDetermined(options, again, rigid);
    if (still.empty()) {
      again.rigid_reprojection_rms = result->rigid_reprojection_rms;
      again.rigid_depth_ratio = result->rigid_depth_ratio;
      again.repair_strength = strength;
      again.warnings.push_back(
          "repaired: the answer with the rule's prior was not determined by "
          "the data (" +
          why + "); re-solved with the shape prior " +
          std::to_string(static_cast<int>(strength)) + " times stronger");
      *result = std::move(again);
      return Status::OK();
    }
  }
  if (!rigid_status.ok() || !rigid.refine.usable) {
    result->warnings.push_back("the answer was not determined by the data (" +
                               why + ") and the rigid answer failed");
    return Status::OK();
  }
  const double rms = result->rigid_reprojection_rms;
  const double depth = result->rigid_depth_ratio;
  const std::vector<std::string> warnings = result->warnings;
  rigid.model = RigidWithBases(rigid.model, options.start.num_bases);
  rigid.priors = rule;
  rigid.priors.term_weights.clear();
  *result = std::move(rigid);
  result->warnings = warnings;
  result->rigid_reprojection_rms = rms;
  result->rigid_depth_ratio = depth;
  result->repair_strength = 0;
  result->warnings.push_back(
      "repaired: the answer was not determined by the data (" + why +
      "), nor with a stronger shape prior; the rigid answer (one shape, "
      "weights 1 and 0) is returned");
  return Status::OK();
}

// Reconstruct() on measurements in any units: every step below is invariant
// to them but Levenberg-Marquardt's damping floor and gradient tolerance,
// which are absolute; Reconstruct() therefore calls it on tracks of unit
// spread. Reconstruct() has checked the options and the measurements.
Status ReconstructInUnits(const ReconstructOptions& options,
                          const Measurements& measurements,
                          ReconstructResult* result) {
  const auto start = std::chrono::steady_clock::now();
  *result = ReconstructResult();
  Unobserved unobserved;
  NRSFM_RETURN_IF_ERROR(
      FindUnobserved(measurements, options.start.num_bases, &unobserved));
  if (!unobserved.empty()) {
    // The options that index observations or frames follow the kept ones.
    ReconstructOptions kept = options;
    kept.problem.observation_weights = WithoutUnobserved(
        options.problem.observation_weights, measurements, unobserved);
    int& reference = kept.problem.smoothness_edges.reference_frame;
    if (reference >= 0) {
      const auto& dropped = unobserved.frames;
      if (std::binary_search(dropped.begin(), dropped.end(), reference)) {
        reference =
            -1;  // a left-out frame: the default choice among the kept ones
      } else {
        reference -= static_cast<int>(
            std::lower_bound(dropped.begin(), dropped.end(), reference) -
            dropped.begin());
      }
    }
    NRSFM_RETURN_IF_ERROR(ReconstructInUnits(
        kept, WithoutUnobserved(measurements, unobserved), result));
    result->model = ExpandModel(result->model, measurements, unobserved);
    result->dropped_points = unobserved.points;
    result->dropped_frames = unobserved.frames;
    result->warnings.insert(result->warnings.begin(),
                            UnobservedWarning(measurements, unobserved));
    result->total_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
            .count();
    return Status::OK();
  }
  PriorDecision decision;
  // The completions and the SVD the prior rule and the starts share.
  StartCache cache(measurements, options.solver.num_threads);
  if (options.priors == PriorMode::kAuto) {
    NRSFM_RETURN_IF_ERROR(DecidePriors(options.prior_rule, measurements,
                                       options.start.num_bases, &decision,
                                       &cache.completions()));
  }
  NRSFM_RETURN_IF_ERROR(
      SolveWithPriors(options, measurements, decision, 1.0, &cache, result));
  if (options.priors == PriorMode::kAuto) {
    NRSFM_RETURN_IF_ERROR(
        Repair(options, measurements, decision, &cache, result));
  }
  const bool at_limit = AtIterationLimit(options, result->refine) ||
                        (result->camera_stage &&
                         AtIterationLimit(options, result->camera_refine));
  if (at_limit) {
    result->warnings.push_back(
        "the refinement stopped at its iteration limit (" +
        std::to_string(options.solver.max_iterations) +
        ") before its tolerances were met; more iterations (max_iterations) "
        "may "
        "still change the result");
  }
  result->depth_ratio = DepthRatio(result->model);
  if (result->depth_ratio > kLargeDepthRatio) {
    std::ostringstream warning;
    warning << std::fixed << std::setprecision(1)
            << "deep shapes: the depth of the result is " << result->depth_ratio
            << " times its extent in the image (above " << kLargeDepthRatio
            << "), as when the shapes were stretched along the view direction; "
               "the data may not determine the depth"
            << (options.priors == PriorMode::kManual
                    ? " (try priors = auto, which re-solves such a result)"
                    : "");
    result->warnings.push_back(warning.str());
  }
  result->largest_view_angle_deg = LargestViewAngleDeg(result->model);
  if (result->largest_view_angle_deg < kLittleRotationDeg) {
    std::ostringstream warning;
    warning << std::fixed << std::setprecision(1)
            << "little rotation: the camera turns at most "
            << result->largest_view_angle_deg
            << " degrees between any two frames; below " << kLittleRotationDeg
            << " degrees the data fix the depth of a deforming shape poorly, "
               "so the depth (z) of this result may be far off";
    result->warnings.push_back(warning.str());
  }
  result->total_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  return Status::OK();
}

// Multiplies everything in input units of `result` (reconstructed from
// tracks divided by `spread`) by the spread: the shapes and translations,
// the RMS values and costs, the noise estimate; the term weights given in
// `options` are returned as given (the rule's own weights are
// dimensionless).
void ToInputUnits(const ReconstructOptions& options, double spread,
                  ReconstructResult* result) {
  result->model.translations *= spread;
  result->model.basis *= spread;
  result->start.reprojection_rms *= spread;
  if (result->start.completion_rms > 0) result->start.completion_rms *= spread;
  if (result->start.rigid_rms > 0) result->start.rigid_rms *= spread;
  for (RefineSummary* summary : {&result->refine, &result->camera_refine}) {
    summary->initial_cost *= spread * spread;
    summary->final_cost *= spread * spread;
    summary->initial_reprojection_rms *= spread;
    summary->reprojection_rms *= spread;
  }
  if (result->priors.noise_rms > 0) result->priors.noise_rms *= spread;
  if (result->rigid_reprojection_rms > 0) {
    result->rigid_reprojection_rms *= spread;
  }
  for (auto& [name, weight] : result->priors.term_weights) {
    const auto given = options.problem.term_weights.find(name);
    if (given != options.problem.term_weights.end()) {
      weight = given->second;
    } else if (const ExtraTerm* term = FindExtraTerm(name);
               term != nullptr && term->weight_in_squared_input_units) {
      weight *= spread * spread;  // the rule's, on tracks of unit spread
    }
  }
}

}  // namespace

Status Reconstruct(const ReconstructOptions& options,
                   const Measurements& measurements,
                   ReconstructResult* result) {
  CHECK(result != nullptr);
  *result = ReconstructResult();
  NRSFM_RETURN_IF_ERROR(options.Check());
  NRSFM_RETURN_IF_ERROR(measurements.Validate());
  const double spread = measurements.ImageSpreadRms();
  if (!(spread > 0.0) || !std::isfinite(spread)) {
    return ReconstructInUnits(options, measurements, result);
  }
  // Tracks of unit spread; what is in input units in the options follows.
  Measurements normalized = measurements;
  normalized.W /= spread;
  ReconstructOptions scaled = options;
  scaled.problem.robust_scale /= spread;
  for (const ExtraTerm& term : ExtraTerms()) {
    const auto it = scaled.problem.term_weights.find(term.name);
    if (term.weight_in_squared_input_units &&
        it != scaled.problem.term_weights.end()) {
      it->second /= spread * spread;
    }
  }
  if (options.solver.progress) {
    scaled.solver.progress = [&options, spread](const IterationReport& report) {
      IterationReport in_units = report;
      in_units.cost *= spread * spread;
      options.solver.progress(in_units);
    };
  }
  const Status status = ReconstructInUnits(scaled, normalized, result);
  ToInputUnits(options, spread, result);
  return status;
}

}  // namespace nrsfm
