// The rule that chooses the extra terms of a reconstruction from the data
// when the caller does not (ReconstructOptions::priors = kAuto). Three facts
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
// 2. Can the basis absorb a rotation error? When 3K ≥ min_basis_fraction · P
//    the shape space spans most of what P points can do, and a slow drift of
//    the rotations is fitted as well by the basis: the rotations drift by
//    several degrees (tens without any term) while the tracks fit as well.
//    A video with such a basis gets the shape's smoothness in time
//    (temporal_shape, at temporal_shape_weight), which ties the object frame
//    over the sequence. With fewer bases the data fix the rotations and the
//    term would only bias the shapes (measured in docs/priors.md), so none
//    is added.
// 3. Does the camera move at constant angular velocity? Asked only when
//    the temporal_shape term is on (2.). The start's camera path (camera 0):
//    with a_L the median over t of
//      |log(R_(t+L) R_tᵀ) − log(R_t R_(t−L)ᵀ)| / L²   (degrees per frame²),
//    the path's acceleration is a_4 − a_1 / 16, clamped at 0: jitter of the start's
//    rotations from frame to frame (noise in the tracks) adds about a_1 to
//    a_1 and a_1 / L² to a_L, so the difference keeps the acceleration of the
//    path itself. When it is below max_path_acceleration_deg (a turntable or
//    an orbiting rig; the starts' values on constant and real camera paths,
//    with and without noise, are measured in docs/priors.md), the refinement
//    keeps it constant with the rotation_acceleration term at
//    rotation_acceleration_weight, strong enough to act as a constraint.
//    Without it the rotations of such data drift by several degrees over the
//    sequence while fitting the tracks as well (the basis absorbs the
//    drift), which is what the object-frame error measures.
// The numbers behind the thresholds and weights are in docs/priors.md.
#ifndef NRSFM_SOLVERS_PRIOR_RULE_H_
#define NRSFM_SOLVERS_PRIOR_RULE_H_

#include <map>
#include <string>

#include "core/measurements.h"
#include "core/model.h"
#include "core/status.h"

namespace nrsfm {

struct PriorRuleOptions {
  double min_track_order = 1.25;            // > 1, dimensionless (motion ratio m_L / m_1)
  double min_basis_fraction = 0.5;          // > 0, 3K / P from which the basis absorbs rotation
  double temporal_shape_weight = 1.0;       // > 0, λ of temporal_shape (problems/extra_terms.h)
  double max_path_acceleration_deg = 0.1;   // ≥ 0, degrees per frame²; 0 = never
  double rotation_acceleration_weight = 1e6;  // > 0, λ of rotation_acceleration

  Status Check() const;
};

// What the rule measured and chose.
struct PriorDecision {
  double track_step = -1;   // m_1 / spread; -1 when F < 2 or no frame pair shares a point
  double track_order = -1;  // max_L m_L / m_1; -1 when F < 8 or m_1 is not defined or 0
  bool video = false;        // track_order ≥ min_track_order
  double path_acceleration_deg = -1;  // a_4 − a_1 / 16 of the start; -1 when not measured (no temporal_shape, F < 9)
  // The weights chosen (empty: none): temporal_shape when a video's basis
  // absorbs rotation (fact 2), rotation_acceleration when its path has
  // constant angular velocity (fact 3).
  std::map<std::string, double> term_weights;
};

// Diagnostic (track_step for L = 1): m_L / spread, the median track motion
// between frames L apart over the image spread; -1 when no such pair of frames shares a visible
// point or the spread is 0.
double MedianTrackStep(const Measurements& measurements, int lag = 1);
// Fact 1: max over L = 2, 4, 8, … ≤ F / 2 of m_L / m_1; -1 when F < 8 or
// m_1 ≤ 0.
double TrackOrder(const Measurements& measurements);
// Fact 3: a_L of camera 0's path in `model`, degrees per frame²; -1 when
// F < 2L + 1.
double MedianPathAccelerationDeg(const Model& model, int lag = 1);
// max(0, a_4 − a_1 / 16) (fact 3 above), degrees per frame²; -1 when F < 9.
double PathAccelerationDeg(const Model& model);

// Facts 1 and 2 for K = num_bases and the temporal_shape weight they imply
// (decision->term_weights).
void DecideVideoPriors(const PriorRuleOptions& options,
                       const Measurements& measurements, int num_bases,
                       PriorDecision* decision);
// Fact 3 when temporal_shape is on, from the start `model`: adds
// rotation_acceleration to decision->term_weights when the path is at
// constant angular velocity.
void DecidePathPrior(const PriorRuleOptions& options, const Model& start,
                     PriorDecision* decision);

// The largest angle, in degrees, between the rotations of camera 0 in any two
// frames of `model`: how far the viewpoint turns over the sequence.
double LargestViewAngleDeg(const Model& model);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_PRIOR_RULE_H_
