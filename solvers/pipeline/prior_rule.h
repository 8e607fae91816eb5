// The rule that chooses the extra terms of a reconstruction from the data
// when the caller does not (ReconstructOptions::priors = kAuto). Four facts
// about the input decide it, each measured, not assumed:
//
// 1. Are the tracks a video (frames in time order)? With m_L the median
//    over t of the RMS over points seen in frames t − L and t (every view)
//    of ||w_tcp − w_(t−L)cp||, the order of the frames shows in how the
//    motion grows with the lag: in a video the tracks move further over L
//    frames than between neighbours, while frames in no order (independent
//    views, random rotations or deformations) are as far apart at every lag.
//    The track order is max over L = 2, 4, 8, … ≤ F/2 of m_L / m_1, and the
//    frames are a video when it is at least min_track_order. Noise adds the
//    same to every m_L, so a noisy video shows its order only at long lags.
//    The track order of real, shuffled, synthetic and noisy re-projected
//    sequences is measured in docs/priors.md. m_1 / spread (track_step) is
//    reported as a diagnostic.
// 2. Do the data alone determine the model? Two reasons that they do not,
//    either of which adds a shape prior:
//    a. misfit: the K-basis model does not explain the tracks (fact 4
//       below: the rank-3K affine fit leaves more than camera_fit_threshold
//       times what noise alone would leave). Real tracks are never exactly
//       of rank 3K; fitted alone, the misfit bends the depth and the camera
//       (the shapes stretch along the view direction; how far is measured in
//       docs/priors.md).
//    b. the basis can absorb a rotation error: 3K ≥ min_basis_fraction · P,
//       the shape space spans most of what P points can do, so a slow drift
//       of the rotations is fitted as well by the basis.
//    The prior: for a video the shape's smoothness in time (temporal_shape
//    at temporal_shape_weight), which also ties the object frame over the
//    sequence; for frames in no order the deformation prior (deformation at
//    deformation_weight: each frame's shape close to one rigid shape up to
//    its scale, problems/deformation_error.h). Both weights are
//    dimensionless: λ = 1 weighs a point's 3D move like a reprojection error
//    of the same length. When neither a. nor b. holds (tracks of exactly
//    K basis shapes, up to noise, with P well above 3K) the data term alone
//    is well-posed and exact, and a prior would only bias it; none is added.
// 3. Does the camera move at constant angular velocity? Asked only when
//    the temporal_shape term is on (2.). The start's camera path (camera 0):
//    with a_L the median over t of
//      |log(R_(t+L) R_tᵀ) − log(R_t R_(t−L)ᵀ)| / L²   (degrees per frame²),
//    the path's acceleration is a_4 − a_1 / 16, clamped at 0: jitter of the
//    start's rotations from frame to frame (noise in the tracks) adds about a_1
//    to a_1 and a_1 / L² to a_L, so the difference keeps the acceleration of
//    the path itself. When it is below max_path_acceleration_deg (a turntable
//    or an orbiting rig; the starts' values on constant and real camera paths,
//    with and without noise, are measured in docs/priors.md), the refinement
//    keeps it constant with the rotation_acceleration term at
//    rotation_acceleration_weight, strong enough to act as a constraint.
//    Without it the rotations of such data drift by several degrees over the
//    sequence while fitting the tracks as well (the basis absorbs the
//    drift), which is what the object-frame error measures.
// 4. How well does the K-basis model explain the tracks, and with how many
//    bases should the camera be estimated? From the singular values of the
//    tracks minus each row's translation (missing entries completed at the
//    largest rank tried, solvers/start/low_rank_completion.h): RSS(r), what a
//    rank-r affine fit leaves, n(r) its free parameters. The noise variance
//    per coordinate σ̂²: for a video from the tracks' third differences in
//    time (TemporalNoiseRms: smooth motion does not enter them, nor does
//    a deformation that changes from frame to frame at random look smooth);
//    otherwise at the rank R = 3R' of the largest R' ≤ min(P, 2FM) / 6 that
//    the data support (what the visible entries allow),
//    σ̂² = RSS(R) / (N − n(R)), as solvers/pipeline/select_num_bases.h does with
//    its reconstructions (a larger R keeps only the smallest singular values of
//    the noise and underestimates it). Without such an R' > K no misfit is
//    declared. The ranks tried never exceed 3R' with 3R' + 1 ≤ min(P, 2FM)
//    and what the visible entries allow. A rank r
//    explains the tracks when
//    sqrt(2 RSS(r) / N) ≤ camera_fit_threshold · max(σ̂ sqrt(2 (N − n(r)) / N),
//    f · spread), f = 10⁻⁶ (10⁻⁴ with missing entries: what the completion
//    reaches on exact data). When rank 3K does not (misfit), the camera is
//    estimated with K_cam > K bases and the K-basis shapes are then fitted with
//    those rotations held (solvers/pipeline/reconstruct.h): a model that cannot
//    explain the tracks bends the rotations to absorb what it cannot fit. K_cam
//    is the smallest K' > K whose rank explains the tracks, at most the largest
//    K' with 3K' ≤ camera_rank_fraction · min(P, 2FM) and K' ≤ kMaxCameraBases
//    (with more, the camera's own extra bases absorb rotation:
//    docs/priors.md). Real tracks, never exactly low-rank, use that cap.
// The numbers behind the thresholds and weights are in docs/priors.md.
#ifndef NRSFM_SOLVERS_PIPELINE_PRIOR_RULE_H_
#define NRSFM_SOLVERS_PIPELINE_PRIOR_RULE_H_

#include <map>
#include <string>

#include "core/measurements.h"
#include "core/model.h"
#include "core/status.h"
#include "solvers/start/low_rank_completion.h"

namespace nrsfm {

struct PriorRuleOptions {
  double min_track_order = 1.25;  // > 1, dimensionless (motion ratio m_L / m_1)
  double min_basis_fraction =
      0.5;  // > 0, 3K / P from which the basis absorbs rotation
  double temporal_shape_weight = 1.0;  // > 0, λ of temporal_shape for a video
  double deformation_weight = 1.0;     // > 0, λ of deformation otherwise
  double max_path_acceleration_deg = 0.1;  // ≥ 0, degrees per frame²; 0 = never
  double rotation_acceleration_weight = 1e6;  // > 0, λ of rotation_acceleration
  double camera_rank_fraction = 0.75;  // in (0, 1): 3K_cam ≤ this · min(P, 2FM)
  double camera_fit_threshold = 1.1;  // ≥ 1, factor over the noise residual
  // The camera stage's function tolerance (relative cost decrease of an
  // accepted step), in (0, 1): it needs the rotations, which settle first;
  // the slow decrease after them is the extra bases absorbing rotation.
  double camera_function_tolerance = 1e-4;

  Status Check() const;
};

// What the rule measured and chose.
struct PriorDecision {
  double track_step =
      -1;  // m_1 / spread; -1 when F < 2 or no frame pair shares a point
  double track_order =
      -1;  // max_L m_L / m_1; -1 when F < 8 or m_1 is not defined or 0
  bool video = false;                 // track_order ≥ min_track_order
  double path_acceleration_deg = -1;  // a_4 − a_1 / 16 of the start; -1 when
                                      // not measured (no temporal_shape, F < 9)
  // Fact 4: whether the K-basis model explains the tracks, the bases the
  // camera is estimated with (K when it does, or without a larger cap), and
  // the noise RMS per coordinate estimated (-1 when not estimated).
  bool model_explains_tracks = true;
  int camera_num_bases = -1;
  double noise_rms = -1;
  // The weights chosen: temporal_shape (a video) or deformation (fact 2),
  // rotation_acceleration when a video's path has constant angular velocity
  // (fact 3).
  std::map<std::string, double> term_weights;
};

// Diagnostic (track_step for L = 1): m_L / spread, the median track motion
// between frames L apart over the image spread; -1 when no such pair of frames
// shares a visible point or the spread is 0.
double MedianTrackStep(const Measurements& measurements, int lag = 1);
// Fact 1: max over L = 2, 4, 8, … ≤ F / 2 of m_L / m_1; -1 when F < 8 or
// m_1 ≤ 0.
double TrackOrder(const Measurements& measurements);
// Fact 3: a_L of camera 0's path in `model`, degrees per frame²; -1 when
// F < 2L + 1.
double MedianPathAccelerationDeg(const Model& model, int lag = 1);
// max(0, a_4 − a_1 / 16) (fact 3 above), degrees per frame²; -1 when F < 9.
double PathAccelerationDeg(const Model& model);

// The bases the camera stage may use at most (fact 4): the reprojection
// cost's compile-time sizes (problems/reprojection_cost_function.h).
inline constexpr int kMaxCameraBases = 16;

// Facts 1, 2 and 4 for K = num_bases: the shape prior's weight
// (decision->term_weights), model_explains_tracks, camera_num_bases and
// noise_rms. Errors only when the low-rank completion of fact 4 fails.
// `completions` (of `measurements`, or null): where the completions are
// kept for the starts (solvers/start/start.h); the decision is the same.
Status DecidePriors(const PriorRuleOptions& options,
                    const Measurements& measurements, int num_bases,
                    PriorDecision* decision,
                    LowRankCompletionMemo* completions = nullptr);

// The largest K' whose rank-3K' fit the tracks support (3K' + 1 ≤ min(P,
// 2FM); with missing entries a view with 3K' + 1 points and a point in
// ⌈3K'/2⌉ views), ≥ 0.
int LargestSupportedBases(const Measurements& measurements);
// The most bases the camera is estimated with (fact 4): the largest K' with
// 3K' ≤ camera_rank_fraction · min(P, 2FM), K' ≤ kMaxCameraBases and
// K' ≤ LargestSupportedBases, ≥ 1. Fact 3 is measured on a start with at
// most this many bases (with more the start's path is not reliable:
// docs/priors.md).
int CameraBasesCap(const PriorRuleOptions& options,
                   const Measurements& measurements);

// Fact 4 alone (fills the three fact-4 fields of `decision`); `video` (fact
// 1) chooses the noise estimate; `completions` as DecidePriors'.
Status AnalyseTrackRank(const PriorRuleOptions& options,
                        const Measurements& measurements, int num_bases,
                        bool video, PriorDecision* decision,
                        LowRankCompletionMemo* completions = nullptr);
// The noise of the tracks per coordinate from their third differences in
// time (a video: the motion is smooth, white noise is not): 1.4826 · the
// median |x_(t+3) − 3x_(t+2) + 3x_(t+1) − x_t| / √20 over every coordinate
// of every point visible in four consecutive frames; -1 when there is none.
double TemporalNoiseRms(const Measurements& measurements);
// Fact 3 when temporal_shape is on, from the start `model`: adds
// rotation_acceleration to decision->term_weights when the path is at
// constant angular velocity.
void DecidePathPrior(const PriorRuleOptions& options, const Model& start,
                     PriorDecision* decision);

// The largest angle, in degrees, between the rotations of camera 0 in any two
// frames of `model`: how far the viewpoint turns over the sequence.
double LargestViewAngleDeg(const Model& model);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_PIPELINE_PRIOR_RULE_H_
