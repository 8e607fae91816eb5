// The rule that chooses the extra terms of a reconstruction from the data
// when the caller does not (ReconstructOptions::priors = kAuto). Two facts
// about the input decide it, each measured, not assumed:
//
// 1. Are the tracks a video? The frame-to-frame motion of the tracks,
//      m_t = RMS over points seen in frames t−1 and t (every view) of
//            ||w_tcp − w_(t−1)cp||,
//    divided by the image spread (Measurements::ImageSpreadRms). The frames
//    are a time-ordered sequence when the median of m_t / spread is below
//    max_track_step. Motion capture and video sit near 0.1 or below (a 5°
//    camera turn per frame moves a point by ~0.09 of the spread); frames in
//    no order (independent views, random rotations) near √2.
// 2. Can the basis absorb a rotation error? When 3K ≥ min_basis_fraction · P
//    the shape space spans most of what P points can do, and a slow drift of
//    the rotations is fitted as well by the basis: the rotations drift by
//    several degrees (tens without any term) while the tracks fit as well.
//    A video with such a basis gets the shape's smoothness in time
//    (temporal_shape, at temporal_shape_weight), which ties the object frame
//    over the sequence. With fewer bases the data fix the rotations and the
//    term would only bias the shapes (superquadric data, P = 60, K = 4:
//    e3D 4e-11 without it, 0.09 with it), so none is added.
// 3. Does the camera move at constant angular velocity? Asked only when
//    the temporal_shape term is on (2.). The start's camera
//    path (camera 0): a_t = |log(R_(t+1) R_tᵀ) − log(R_t R_(t−1)ᵀ)| in
//    degrees per frame². When the median of a_t is below
//    max_path_acceleration_deg (a turntable or an orbiting rig: a start from
//    data at exactly constant speed is at ~0.01°/frame²; a hand-held camera
//    at ~1°/frame²), the refinement keeps it constant with the
//    rotation_acceleration term at rotation_acceleration_weight, strong
//    enough to act as a constraint. Without it the rotations of such data
//    drift by several degrees over the sequence while fitting the tracks as
//    well (the basis absorbs the drift), which is what the object-frame
//    error measures.
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
  double max_track_step = 0.3;              // > 0, dimensionless (fraction of the image spread)
  double min_basis_fraction = 0.5;          // > 0, 3K / P from which the basis absorbs rotation
  double temporal_shape_weight = 1.0;       // > 0, λ of temporal_shape (problems/extra_terms.h)
  double max_path_acceleration_deg = 0.1;   // ≥ 0, degrees per frame²; 0 = never
  double rotation_acceleration_weight = 1e6;  // > 0, λ of rotation_acceleration

  Status Check() const;
};

// What the rule measured and chose.
struct PriorDecision {
  double track_step = -1;  // median m_t / spread; -1 when F < 2 or no frame pair shares a point
  bool video = false;
  bool basis_absorbs_rotation = false;  // 3K ≥ min_basis_fraction · P
  double path_acceleration_deg = -1;  // median a_t of the start; -1 when not measured (no temporal_shape, F < 3)
  bool constant_angular_velocity = false;
  std::map<std::string, double> term_weights;  // the weights chosen (empty: none)
};

// Fact 1: the median normalised frame-to-frame track motion, -1 when no
// consecutive frames share a visible point.
double MedianTrackStep(const Measurements& measurements);
// Fact 2: the median angular acceleration of camera 0's path in `model`,
// degrees per frame²; -1 when F < 3.
double MedianPathAccelerationDeg(const Model& model);

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
