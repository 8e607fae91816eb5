#include "solvers/pipeline/reconstruct.h"

#include <glog/logging.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

#include "core/model/enum_names.h"
#include "core/model/option_checker.h"
#include "problems/extra_terms.h"
#include "solvers/pipeline/drop_unobserved.h"
#include "solvers/pipeline/perspective.h"
#include "solvers/pipeline/stages.h"

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
  check.Require(
      std::isfinite(depth) && depth >= 0.0,
      "depth must be >= 0 (0: fx of camera 0), got " + std::to_string(depth));
  check.Require(CameraModelName(camera) != std::string("unknown"),
                "invalid camera model");
  check.Require(priors == PriorMode::kManual || !any_weight,
                "term weights are given but priors = auto chooses them; set "
                "priors = manual to use your own");
  return check.status();
}

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
    ReconstructOptions kept = options;
    kept.problem = WithoutUnobserved(options.problem, measurements, unobserved);
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
  if (options.camera == CameraModel::kPerspective) {
    ReconstructOptions weak = options;
    weak.camera = CameraModel::kWeakPerspective;
    NRSFM_RETURN_IF_ERROR(ReconstructInUnits(weak, measurements, result));
    if (options.solver.stop_requested && options.solver.stop_requested()) {
      return Status::OK();
    }
    ProblemOptions problem = options.problem;
    problem.term_weights = result->priors.term_weights;
    Model model;
    RefineSummary summary;
    const Status status = RefinePerspective(
        problem, options.solver, measurements, result->model, &model, &summary);
    if (!status.ok()) {
      result->warnings.push_back(status.message() +
                                 "; the weak-perspective answer is returned");
      return Status::OK();
    }
    result->weak_perspective_refine = result->refine;
    result->refine = summary;
    result->model = std::move(model);
    result->depth_ratio = DepthRatio(result->model);
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
  result->model.depths *= spread;
  if (result->model.camera == CameraModel::kPerspective) {
    result->model.intrinsics *= spread;
  }
  result->model.basis *= spread;
  result->start.reprojection_rms *= spread;
  if (result->start.completion_rms > 0) result->start.completion_rms *= spread;
  if (result->start.rigid_rms > 0) result->start.rigid_rms *= spread;
  for (RefineSummary* summary : {&result->refine, &result->camera_refine,
                                 &result->weak_perspective_refine}) {
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
  if (options.camera == CameraModel::kPerspective &&
      measurements.intrinsics.cols() != measurements.num_cameras) {
    return Status::Error(
        "the perspective camera needs the intrinsics of every camera: a Kcam "
        "variable in the .mat input, or intrinsics fx,fy,cx,cy");
  }
  const double spread = measurements.ImageSpreadRms();
  if (!(spread > 0.0) || !std::isfinite(spread)) {
    return ReconstructInUnits(options, measurements, result);
  }
  // Tracks of unit spread; what is in input units in the options follows.
  Measurements normalized = measurements;
  normalized.W /= spread;
  normalized.intrinsics /= spread;
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
  if (status.ok() && result->model.camera == CameraModel::kPerspective) {
    const double depth =
        options.depth > 0.0 ? options.depth : measurements.intrinsics(0, 0);
    if (!SetMeanDepth(depth, &result->model)) {
      result->warnings.push_back(
          "the first frame's points are not in front of the camera; the "
          "depth convention could not be applied");
    }
  }
  return status;
}

}  // namespace nrsfm
