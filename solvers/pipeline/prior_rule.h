// The rule that chooses the extra terms of a reconstruction from the data
// when the caller does not (ReconstructOptions::priors = kAuto). What it
// measures, each a function below:
// 1. whether the tracks are a video (TrackOrder ≥ min_track_order);
// 2. whether the rank-3K fit leaves only round-off (exactly_low_rank): only
//    such tracks, with 3K < min_basis_fraction · P, are refined with the
//    data term alone; every other input gets a shape prior — temporal_shape
//    for a video, deformation otherwise;
// 3. on the start: whether the camera path is a candidate for the
//    constant-angular-velocity prior (PathAccelerationDeg), and a weaker
//    temporal_shape weight from how smoothly the start deforms
//    (DeformationCoherence); Reconstruct() keeps the full weight and the path
//    prior only when the tracks are fitted about as well with them;
// 4. how many bases explain the tracks (AnalyseTrackRank): the camera is
//    estimated with K_cam ≥ K bases;
// 5. several cameras: they are taken to be a rig, held by rigidity.
// docs/priors.md derives each and has the measurements behind the constants.
#ifndef NRSFM_SOLVERS_PIPELINE_PRIOR_RULE_H_
#define NRSFM_SOLVERS_PIPELINE_PRIOR_RULE_H_

#include <map>
#include <string>

#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"
#include "problems/reprojection_cost_function.h"
#include "solvers/start/low_rank_completion.h"

namespace nrsfm {

struct PriorRuleOptions {
  double min_track_order = 1.25;  // > 1, dimensionless (motion ratio m_L / m_1)
  // > 0, 3K / P from which the basis absorbs rotation.
  double min_basis_fraction = 0.5;
  // > 0, λ of temporal_shape for a video whose start deforms smoothly
  // (deformation coherence 1).
  double temporal_shape_weight = 1.0;
  // In (0, temporal_shape_weight]: the alternative λ of temporal_shape when
  // consecutive frames of the start deform independently (coherence 0); in
  // between λ = temporal_shape_weight · (this / it)^((1 − c)⁴).
  double min_temporal_shape_weight = 1e-4;
  double deformation_weight = 1.0;  // > 0, λ of deformation otherwise
  // > 0, λ of rigidity with several cameras (a rig), in (spread / rad)²:
  // the rule's weight on tracks of unit spread.
  double rigidity_weight = 100.0;
  // ≥ 0, degrees per frame²: the path prior is tried when the start's path
  // acceleration is below it; 0 = never.
  double max_path_acceleration_deg = 1.0;
  double rotation_acceleration_weight = 1e6;  // > 0, λ of rotation_acceleration
  // ≥ 1: the full priors (temporal_shape at its full weight, the path
  // prior) are kept when the refinement with them fits the tracks within
  // this factor (reprojection RMS) of the alternative's.
  double max_prior_fit_ratio = 1.5;
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
  // m_1 / spread; -1 when F < 2 or no frame pair shares a point
  double track_step = -1;
  // max_L m_L / m_1; -1 when F < 8 or m_1 is not defined or 0
  double track_order = -1;
  bool video = false;                 // track_order ≥ min_track_order
  double path_acceleration_deg = -1;  // a_4 − a_1 / 16 of the start; -1 when
                                      // not measured (no temporal_shape, F < 9)
  // Fact 4: whether the K-basis model explains the tracks, the bases the
  // camera is estimated with (K when it does, or without a larger cap), and
  // the noise RMS per coordinate estimated (-1 when not estimated).
  bool model_explains_tracks = true;
  int camera_num_bases = -1;
  double noise_rms = -1;
  // Whether the rank-3K affine fit leaves no more than round-off
  // (noise-free tracks of K basis shapes): only then may the data term
  // stand alone.
  bool exactly_low_rank = false;
  // DeformationCoherence of the start (-1 when not measured): how smoothly
  // the start's object-frame shape deforms from frame to frame.
  double deformation_coherence = -1;
  // temporal_shape's weight from the coherence (DecideStartPriors), the
  // alternative to the full weight in term_weights; -1 when not decided.
  double temporal_shape_alternative = -1;
  // The reprojection RMS of the refinement with the full priors (temporal
  // shape at its full weight, the path prior) over the alternative's (the
  // coherence weight, no path prior); -1 when they were not compared.
  double prior_fit_ratio = -1;
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
inline constexpr int kMaxCameraBases = kMaxStaticBases;

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
// The weights decided on the start `start` (with temporal_shape on, from
// DecidePriors): temporal_shape at its full weight, with the path prior
// (rotation_acceleration) when PathAccelerationDeg of `path_start` is below
// max_path_acceleration_deg, and the alternative (temporal_shape_alternative)
// from the start's DeformationCoherence, continuous in it. Reconstruct()
// keeps the full priors when the tracks are fitted within
// max_prior_fit_ratio with them, else the alternative without the path
// prior. `strength` (≥ 1) multiplies the shape prior's weight: a re-solve of
// a result the data did not determine (solvers/pipeline/reconstruct.h).
// `path_start` is the start the path is measured on (one with at most
// CameraBasesCap bases).
void DecideStartPriors(const PriorRuleOptions& options, const Model& start,
                       const Model& path_start, double strength,
                       PriorDecision* decision);
// How smoothly the object-frame shape of `model` deforms in time, in [0, 1]:
// 1 − Σ_t ||S_t − S_(t−1)||² / (2 (F − 1) / F · Σ_t ||S_t − S̄||²) clamped,
// S̄ the mean shape over the frames (camera 0's frames; NaN points
// skipped). 1 for a shape that deforms slowly (or not at all), about 0 when
// consecutive frames deform independently; -1 when F < 2.
double DeformationCoherence(const Model& model);

// The largest angle, in degrees, between the rotations of camera 0 in any two
// frames of `model`: how far the viewpoint turns over the sequence.
double LargestViewAngleDeg(const Model& model);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_PIPELINE_PRIOR_RULE_H_
