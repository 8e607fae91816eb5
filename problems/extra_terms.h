// The residual blocks beyond the data term (DESIGN.md §2), each with its own
// weight in ProblemOptions (0 = off, the default):
//
//   smoothness_weight λ_s          Delaunay-neighbour smoothness of the basis,
//                                  problems/smoothness_error.h with the edges
//                                  of problems/delaunay_edges.h
//   rigidity_weight λ_r            multi-camera rigidity (M ≥ 2),
//                                  problems/rigidity_error.h
//   temporal_weights_weight λ_l    l_t − l_{t−1}, problems/temporal_error.h
//   temporal_rotations_weight λ_R  log(R_tc R_{t−1,c}ᵀ), problems/temporal_error.h
//   temporal_shape_weight λ_S      S_t[:, p] − S_{t−1}[:, p], problems/temporal_error.h
//   rotation_acceleration_weight λ_A  change of log(R_tc R_{t−1,c}ᵀ), same file
//
// Each term's cost is λ times its unweighted cost (the functors apply √λ);
// units are in the functors' headers. Constant flags of ProblemOptions apply
// to the blocks these terms add too; the rig blocks (ω_rig_c, s_rig_c, one
// per camera c ≥ 1, Model::rig_rotations / rig_scales) are free unless
// constant_rig.
//
// Structure (problems/linear_solver_choice.h): smoothness residuals couple
// two point blocks, so with λ_s > 0 the points are no longer an independent
// set; the temporal and rigidity residuals couple only non-point blocks
// (consecutive frames, the views of one frame and the rig) or, for the
// shape prior, one point with two frames' weights, which keeps the points
// eliminable.
#ifndef NRSFM_PROBLEMS_EXTRA_TERMS_H_
#define NRSFM_PROBLEMS_EXTRA_TERMS_H_

#include "core/status.h"
#include "problems/problem_builder.h"

namespace nrsfm {

struct ExtraTermCounts {
  int smoothness = 0;          // residual blocks: neighbour edges
  int rigidity = 0;            // (t, c ≥ 1) pairs
  int temporal_weights = 0;    // t = 1 … F − 1
  int temporal_rotations = 0;  // (t ≥ 1, c) pairs
  int temporal_shape = 0;      // (t ≥ 1, p) pairs
  int rotation_acceleration = 0;  // (1 ≤ t ≤ F − 2, c) pairs
  int reference_frame = -1;    // frame of the Delaunay triangulation (-1: no smoothness)
};

// Adds the residual blocks of every term whose weight is non-zero to the
// builder's problem; call after builder->AddReprojectionTerms(options).
// Errors (adding nothing) on invalid options, on rigidity_weight > 0 with
// fewer than 2 cameras, or on a reference view that cannot be triangulated.
Status AddExtraTerms(const ProblemOptions& options, ProblemBuilder* builder,
                     ExtraTermCounts* counts);

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_EXTRA_TERMS_H_
