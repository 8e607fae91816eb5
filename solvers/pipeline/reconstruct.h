// Reconstruct(): the whole pipeline the nrsfm tool and the benchmarks run —
// a closed-form start (solvers/start/start.h) and the refinement of the one
// Ceres problem (solvers/refine/refine.h).
#ifndef NRSFM_SOLVERS_PIPELINE_RECONSTRUCT_H_
#define NRSFM_SOLVERS_PIPELINE_RECONSTRUCT_H_

#include <string>
#include <vector>

#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"
#include "problems/problem_options.h"
#include "solvers/pipeline/prior_rule.h"
#include "solvers/refine/refine.h"
#include "solvers/refine/solver_options.h"
#include "solvers/start/start.h"

namespace nrsfm {

// Who chooses the extra terms (problems/extra_terms.h).
enum class PriorMode {
  kAuto,    // the rule of solvers/pipeline/prior_rule.h, from the data and the
            // start; problem.term_weights must then be empty
  kManual,  // exactly problem.term_weights (empty: the data term alone)
};
// "auto", "manual"; the error lists them.
const char* PriorModeName(PriorMode mode);
Status ParsePriorMode(const std::string& name, PriorMode* mode);

// Everything a reconstruction needs, each fact once. The defaults are the
// pipeline the project recommends for any input (docs/priors.md has what
// it was measured on).
struct ReconstructOptions {
  StartOptions start;  // the closed-form start, including K (start.num_bases)
  ProblemOptions problem;  // what the Ceres problem holds and refines
  SolverOptions solver;    // how it is solved
  PriorMode priors = PriorMode::kAuto;
  PriorRuleOptions prior_rule;  // used when priors = kAuto
  // The camera (docs/camera.md). kPerspective needs the measurements'
  // intrinsics: the weak-perspective answer is found first, then refined
  // as a pinhole model (solvers/pipeline/perspective.h).
  CameraModel camera = CameraModel::kWeakPerspective;
  // Perspective only: the global scale gauge, the mean depth of the first
  // frame's points in the output's units; 0 = fx of camera 0 (so a unit is
  // about a pixel at that depth). ≥ 0.
  double depth = 0.0;

  // Each part's Check(), with the part named in the message; errors on term
  // weights given with priors = kAuto, on a negative or non-finite depth.
  Status Check() const;
};

struct ReconstructResult {
  Model model;  // the refined model (the start if refine.usable is false)
  StartSummary start;    // the start kept: method, its RMS, its time
  RefineSummary refine;  // the (last) refinement: costs, RMS, iterations, times
  // camera = kPerspective: the weak-perspective answer's refinement (`refine`
  // is then the pinhole one).
  RefineSummary weak_perspective_refine;
  // Whether the refinement ran in two stages (priors = auto with a shape
  // prior and K_cam = priors.camera_num_bases > K: the camera stage, then
  // the shape stage with its rotations held), and the camera stage's
  // refinement (with K_cam bases). With K_cam = K the camera stage is the
  // only refinement (`refine`) and camera_stage is false.
  bool camera_stage = false;
  RefineSummary camera_refine;
  // What the prior rule measured and the term weights the refinement used
  // (with priors = kManual: only term_weights, the caller's).
  PriorDecision priors;
  // The largest angle between two frames' camera-0 rotations of the result,
  // degrees, and the warnings about the result as a whole (left-out points
  // or frames, the iteration limit reached, little rotation).
  double largest_view_angle_deg = 0;
  // DepthRatio(model): a result far deeper than wide was stretched along
  // the view direction (a depth the data do not determine); above
  // kLargeDepthRatio a warning says so.
  double depth_ratio = 0;
  std::vector<std::string> warnings;
  // priors = auto: the rigid answer's reprojection RMS and depth ratio
  // (K = 1, the rigid start, no extra term; -1 when it was not needed or
  // failed), against which the result was checked, and the repair: 1 = none, s
  // > 1 = the shape prior s times stronger, 0 = the rigid answer returned (see
  // Reconstruct()).
  double rigid_reprojection_rms = -1;
  double rigid_depth_ratio = -1;
  double repair_strength = 1;
  // Points and frames with too few observations, left out of the solve and
  // NaN in `model` (solvers/pipeline/drop_unobserved.h); a warning names them.
  // The summaries above are of the kept measurements.
  std::vector<int> dropped_points;
  std::vector<int> dropped_frames;
  double total_seconds = 0;  // wall time of Reconstruct()
};

// Below this largest view angle a warning says the depth is weakly
// determined by the data (measured in docs/robustness.md).
inline constexpr double kLittleRotationDeg = 60.0;

// The depth ratio of a model: the RMS depth over the RMS image-plane
// coordinate (per coordinate) of camera 0's centred shapes X_t over every
// frame and point; NaN (left-out) points are skipped, 0 when nothing is
// left. A rigid object seen from a turning camera reads about 1 or less,
// shapes stretched along the view direction (a depth the data do not
// determine) far more: the values measured on real sequences are in
// docs/priors.md.
double DepthRatio(const Model& model);
// Above this depth ratio Reconstruct() warns that the depth may not be
// determined by the data.
inline constexpr double kLargeDepthRatio = 3.0;
// The shape prior's strengths a result the data do not determine is
// re-solved with, in turn (Reconstruct()).
inline constexpr double kRepairStrengths[] = {10.0, 100.0};

// When two starts are refined (the rule below), their refinements run side
// by side in lockstep (solvers/pipeline/two_starts.h) when the measurements
// have at most this many visible observations, so that the two problems fit in
// memory together (a refinement's memory per observation: measured in
// docs/performance.md). Larger inputs refine one after the other.
inline constexpr int kMaxObservationsForTwoAtOnce = 1000000;

// The pipeline (docs/priors.md derives each step and has its measurements).
// With priors = auto the rule of solvers/pipeline/prior_rule.h chooses the
// terms and K_cam ≥ K, the bases the camera is estimated with:
// 1. Camera stage: the start with K_cam bases and its refinement. A video
//    with temporal_shape starts from the corrective triple alone (its
//    weight and the path prior decided on that start, the path measured on
//    a start with at most CameraBasesCap bases, computed beside it): the full
//    priors (temporal_shape at its full weight, the path prior when a
//    candidate) are refined beside the alternative (the coherence weight, no
//    path prior) and kept when the tracks are fitted within
//    max_prior_fit_ratio with them (progress reports are the full priors').
//    Otherwise the factorization and rigid starts are refined side by side
//    (solvers/pipeline/two_starts.h) and the lower cost kept. With a shape
//    prior the stage stops at prior_rule.camera_function_tolerance.
// 2. Shape stage, when K_cam > K: the shapes reduced to K bases
//    (ReduceNumBases), refined with the rotations held.
// 3. Repair: a result that is not usable, ended at its iteration limit or
//    is deeper than kLargeDepthRatio is checked against the tool's own rigid
//    answer (K = 1, rigid start, no term): usable, ended by a tolerance, no
//    deeper than max(kLargeDepthRatio, the rigid answer's DepthRatio),
//    fitting the tracks no worse. One that fails is re-solved with the shape
//    prior kRepairStrengths times stronger; when none passes, the rigid answer
//    is returned with K bases (weights 1, 0, …). result->repair_strength and a
//    warning say which.
// With priors = manual: the given start (auto: both starts) with exactly the
// given terms, one stage, no repair. Points and frames with too few
// observations are left out first (solvers/pipeline/drop_unobserved.h) and
// are NaN in result->model. Everything runs on the tracks divided by their
// spread and is scaled back: shapes, translations, RMS values, costs,
// noise_rms and the λ in input units (a λ that was given is returned as
// given); the solver's own reports describe the normalised problem.
// Errors on invalid options or measurements and when the start fails (see
// ComputeStart); a refinement that is not usable is reported in
// result->refine.usable, with result->model left at the start.
Status Reconstruct(const ReconstructOptions& options,
                   const Measurements& measurements, ReconstructResult* result);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_PIPELINE_RECONSTRUCT_H_
