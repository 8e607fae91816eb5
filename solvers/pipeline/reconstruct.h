// Reconstruct(): the whole pipeline the nrsfm tool and the benchmarks run —
// a closed-form start (solvers/start/start.h) and the refinement of the one
// Ceres problem (solvers/refine/refine.h).
#ifndef NRSFM_SOLVERS_PIPELINE_RECONSTRUCT_H_
#define NRSFM_SOLVERS_PIPELINE_RECONSTRUCT_H_

#include <string>
#include <vector>

#include "core/measurements.h"
#include "core/model.h"
#include "core/status.h"
#include "problems/problem_options.h"
#include "solvers/pipeline/prior_rule.h"
#include "solvers/refine/refine.h"
#include "solvers/refine/solver_options.h"
#include "solvers/start/start.h"

namespace nrsfm {

// Who chooses the extra terms (problems/extra_terms.h).
enum class PriorMode {
  kAuto,  // the rule of solvers/pipeline/prior_rule.h, from the data and the
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

  // Each part's Check(), with the part named in the message; errors on term
  // weights given with priors = kAuto.
  Status Check() const;
};

struct ReconstructResult {
  Model model;  // the refined model (the start if refine.usable is false)
  StartSummary start;    // the start kept: method, its RMS, its time
  RefineSummary refine;  // the (last) refinement: costs, RMS, iterations, times
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

// When two starts are refined (the rule below), their refinements run side
// by side in lockstep (solvers/pipeline/two_starts.h) when the measurements
// have at most this many visible observations, so that the two problems fit in
// memory together (a refinement's memory per observation: measured in
// docs/performance.md). Larger inputs refine one after the other.
inline constexpr int kMaxObservationsForTwoAtOnce = 1000000;

// The pipeline. With priors = auto the rule of solvers/pipeline/prior_rule.h
// decides the shape prior (temporal_shape for a video, deformation otherwise;
// none when the K-basis model explains the tracks and its basis cannot absorb
// rotation) and K_cam ≥ K, the bases the camera is estimated with.
// 1. Camera stage: the start with K_cam bases and its refinement. With
//    start.method = auto:
//    - a video with the temporal_shape prior: the triple start alone. Its
//      rotations come from an exact corrective triple of the rank-3K
//      factorisation, the ones the temporal terms then hold in place; the
//      factorisation and rigid starts' rotations are further off on motion
//      capture, and the refinement does not leave their basin (measured in
//      docs/priors.md). The path prior (solvers/pipeline/prior_rule.h
//      DecidePathPrior) is decided on the start, or, when K_cam is above
//      CameraBasesCap, on a second start with that many bases, computed
//      beside the first (core/parallel_for.h; num_threads ≥ 2 and at most
//      kMaxObservationsForTwoAtOnce observations; the same starts for any
//      thread count).
//    - otherwise both the factorization and the rigid starts are refined and
//      the lower refined cost is kept (a usable solution before an unusable
//      one). A start's own reprojection error does not tell which basin it
//      is in: the start that fits the tracks better can refine to the worse
//      result (measured in docs/factorization.md, section 7). The two
//      refinements run side by side in lockstep, at once with num_threads ≥
//      2 (each on num_threads / 2 threads) or in turns with one; once one has
//      converged after n LM iterations, the other is abandoned when it has
//      run 2n + 10 iterations without reaching a lower cost
//      (solvers/pipeline/two_starts.h; inputs above
//      kMaxObservationsForTwoAtOnce: one after the other, the factorization
//      start's to its end, the rigid start's abandoned by the same rule when
//      the first converged). Progress reports and stop requests reach the
//      caller's thread, the factorization refinement's reports first.
//    With a shape prior the camera stage stops at
//    prior_rule.camera_function_tolerance: its rotations settle first, and
//    the slow decrease after them is the basis absorbing rotation, which
//    moves the camera away from the truth (how long it runs on drink:
//    docs/priors.md); result->camera_refine is its summary.
// 2. Shape stage, with a shape prior and K_cam > K: the camera stage's
//    shapes reduced to K bases by ReduceNumBases (core/model.h), refined
//    with the camera stage's rotations held and the same shape prior
//    (result->refine), to the solver's own tolerance. The rotations of the
//    result are the camera stage's. With K_cam = K there is no shape stage:
//    the camera stage's result is the answer (result->refine, and
//    result->camera_stage is false); a shape stage would only polish it with
//    the rotations held, which measured no more accurate and up to 12× the
//    LM steps on noisy tracks (docs/performance.md).
// With priors = manual: the given start (auto: both starts, as above) with
// K bases refined with exactly the given terms, one stage.
// result->start.method says which start was kept.
// Points and frames with too few observations for the model with K bases
// are first left out (solvers/pipeline/drop_unobserved.h; observation_weights
// and smoothness_edges.reference_frame follow the kept ones, a left-out
// reference frame becomes the default choice): the rest is reconstructed as
// above and the left-out ones are NaN in result->model, listed in
// result->dropped_points / dropped_frames and named in a warning.
// Units: everything above runs on the tracks divided by their spread
// (Measurements::ImageSpreadRms), with robust_scale and the λ of terms
// whose weight is in (input units)² divided likewise, and the result is
// scaled back: shapes, translations, RMS values, costs, noise_rms and those
// λ are in input units (a λ that was given is returned as given). The
// solvers' damping floor and gradient tolerance are absolute, so without
// this the same tracks in millimetres and in metres would refine
// differently (docs/priors.md, units). Only the
// progress callback's cost is in input units too; the solver's own reports
// (result->refine.ceres_report) describe the normalised problem.
// Errors on invalid options or measurements and when the start fails (see
// ComputeStart); a refinement that is not usable is reported in
// result->refine.usable, with result->model left at the start.
Status Reconstruct(const ReconstructOptions& options,
                   const Measurements& measurements, ReconstructResult* result);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_PIPELINE_RECONSTRUCT_H_
