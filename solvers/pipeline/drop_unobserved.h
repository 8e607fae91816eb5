// Points and frames with too few observations to be reconstructed: found
// before the start, left out of the solve, named in a warning and put back
// into the result as NaN (Reconstruct(), solvers/pipeline/reconstruct.h).
//
// The rule is what the refined model needs, so that every parameter is fixed
// by the data term (the start needs more and adapts, below):
//   - a point's basis column b_p has 3K unknowns and each view that sees the
//     point gives 2 equations, so a point seen in fewer than
//     MinViewsPerPoint(K) = max(2, ⌈3K / 2⌉) views (all cameras counted) is
//     left out: its 3-D position would be whatever the solver's damping left
//     it at;
//   - a view's pose has 3 (rotation) + 2 (translation) + 1 (scale, cameras
//     c ≥ 1) unknowns and the frame's weights K more, so a frame is left out
//     when one of its views (any camera) sees fewer than
//     MinPointsPerView(K) = max(4, ⌈(K + 5) / 2⌉) of the points that are
//     kept; the whole frame goes (every camera), since the model's weights
//     l_t are per frame.
// The start asks more (a rank-3K' completion needs every view to see
// 3K' + 1 points and every point ⌈3K' / 2⌉ views) and uses the largest
// K' ≤ K the kept data allow, so a rarely seen point is left out rather
// than lowering K' for the whole start (docs/factorization.md, section 1).
// Leaving out a frame takes views away from the points and leaving out a
// point takes points away from the views, so the two are applied in turn
// (points first) until neither leaves out anything more. Complete
// measurements leave nothing out (every view sees all P ≥ 3K + 1 points),
// and so do measurements too small for K (F < 2, 2F < 3K + 1 or
// P < 3K + 1): ComputeStart() reports those with its own errors.
//
// The result on the full index (ExpandModel): every parameter of a left-out
// frame (its rotations, translations, scales and weights) and the basis
// column of a left-out point are NaN, so its shapes, points_camera.csv and
// points_object.csv hold NaN there. They are not placed by any prior (the
// smoothness or temporal terms could interpolate them; they do not). With
// temporal terms the frames either side of a left-out frame are treated as
// neighbours. Errors and metrics of the result cover what was kept.
#ifndef NRSFM_SOLVERS_PIPELINE_DROP_UNOBSERVED_H_
#define NRSFM_SOLVERS_PIPELINE_DROP_UNOBSERVED_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"
#include "problems/problem_options.h"

namespace nrsfm {

// What the model with K bases needs (header): views per point, points per
// view.
int MinViewsPerPoint(int num_bases);
int MinPointsPerView(int num_bases);

struct Unobserved {
  int num_bases = 0;        // the K the rule was applied for
  std::vector<int> points;  // left-out point indices of the input, ascending
  std::vector<int> frames;  // left-out frame indices of the input, ascending
  bool empty() const { return points.empty() && frames.empty(); }
};

// Applies the rule above to valid measurements for a reconstruction with
// K = num_bases (≥ 1). Errors when what would be kept is too little to
// reconstruct with K (F < 2, 2F < 3K + 1 or P < 3K + 1 kept), naming the
// counts.
Status FindUnobserved(const Measurements& measurements, int num_bases,
                      Unobserved* unobserved);

// The measurements without the left-out points and frames; the kept ones
// keep their order (renumbered 0, 1, …).
Measurements WithoutUnobserved(const Measurements& measurements,
                               const Unobserved& unobserved);

// Per-observation values of `measurements`, (F·M) × P like
// Measurements::visible (e.g. ProblemOptions::observation_weights), for the
// observations WithoutUnobserved(measurements) keeps, in its order. An
// array of another size (an empty one too) is returned unchanged, so that
// whoever checks the size against the measurements reports it.
Eigen::ArrayXXd WithoutUnobserved(const Eigen::ArrayXXd& per_observation,
                                  const Measurements& measurements,
                                  const Unobserved& unobserved);

// The indices 0 … count − 1 that are not in the ascending `left_out`, in
// order (the kept frames or points).
std::vector<int> KeptIndices(int count, const std::vector<int>& left_out);

// The problem options for WithoutUnobserved(measurements): the observation
// weights of the kept observations, the smoothness reference frame
// renumbered (a left-out one becomes -1, the default choice).
ProblemOptions WithoutUnobserved(const ProblemOptions& options,
                                 const Measurements& measurements,
                                 const Unobserved& unobserved);

// The model of the kept frames and points (the inverse of ExpandModel).
Model WithoutUnobserved(const Model& model, const Unobserved& unobserved);

// A model of WithoutUnobserved(measurements) on the full index of
// `measurements` (F, M, P of the input, K of the model): the kept frames'
// and points' values, NaN for the left-out ones (see the header); rig
// rotations and scales unchanged.
Model ExpandModel(const Model& kept, const Measurements& measurements,
                  const Unobserved& unobserved);

// One line for the result's warnings, e.g. "left out of the reconstruction
// (a start needs every point seen in at least 2 views and every frame's
// views to see at least 4 points), NaN in the result: point 40 (seen in 1
// view); frame 3 (sees 2 points)". Lists at most 20 of each, then "and N
// more".
std::string UnobservedWarning(const Measurements& measurements,
                              const Unobserved& unobserved);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_PIPELINE_DROP_UNOBSERVED_H_
