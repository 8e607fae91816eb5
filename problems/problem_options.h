// What the one Ceres problem of a reconstruction holds and which of its
// blocks are refined (docs/problem.md). ProblemBuilder (problems/
// problem_builder.h) and AddExtraTerms (problems/extra_terms.h) read these
// options; Refine() (solvers/refine/refine.h) takes them as they are.
#ifndef NRSFM_PROBLEMS_PROBLEM_OPTIONS_H_
#define NRSFM_PROBLEMS_PROBLEM_OPTIONS_H_

#include <Eigen/Core>
#include <map>
#include <string>

#include "core/model/status.h"
#include "problems/delaunay_edges.h"

namespace nrsfm {

// Robust loss ρ of the data (reprojection) term, s = ||e||², a = robust_scale.
enum class RobustLoss {
  kNone,    // ρ(s) = s, least squares
  kHuber,   // ρ(s) = s for s ≤ a², 2a√s − a² beyond
  kCauchy,  // ρ(s) = a² log(1 + s / a²)
};
// "none", "huber", "cauchy"; the error names the bad value and lists these.
const char* RobustLossName(RobustLoss loss);
Status ParseRobustLoss(const std::string& name, RobustLoss* loss);

struct ProblemOptions {
  // Kinds of block held at their current value (every block of the kind);
  // all others are refined.
  bool constant_rotations = false;     // every ω_tc
  bool constant_translations = false;  // every T_tc
  bool constant_weights = false;       // every l_t
  bool constant_basis = false;         // every b_p
  bool constant_scales = false;  // every s_tc, c ≥ 1 (no effect for M = 1)
  bool constant_rig = false;  // rig rotations and scales (rigidity term only)

  // Robust loss of each observation's squared distance, with its scale a in
  // input units (the residual distance where the loss stops being quadratic).
  RobustLoss robust_loss = RobustLoss::kNone;
  double robust_scale = 1.0;  // a > 0, input units

  // Per-observation weights w_obs ≥ 0, (F·M) × P like Measurements::visible;
  // empty = every weight is 1. An observation's cost is w_obs · ρ(||e||²)
  // (e in input units), so robust_scale keeps its meaning under any weight.
  // Entries of invisible observations are ignored; a visible observation with
  // w_obs = 0 gets no residual.
  Eigen::ArrayXXd observation_weights;

  // Weight λ ≥ 0 of each extra term, keyed by the term's name in the table
  // of problems/extra_terms.h (e.g. {"temporal_shape", 1.0}); λ multiplies
  // the term's cost, and a term that is absent or has λ = 0 is not in the
  // problem. The units of each λ are in the table.
  std::map<std::string, double> term_weights;
  // The neighbour edges of the smoothness term.
  DelaunayEdgesOptions smoothness_edges;

  // λ of the term `name` (0 when absent).
  double TermWeight(const std::string& name) const;

  // Errors on a robust_scale that is not positive and finite, negative or
  // non-finite observation weights, a term name that is not in the table, a
  // term weight that is negative or not finite, invalid smoothness_edges,
  // and when every kind of block of the data term is constant.
  Status Check() const;
};

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_PROBLEM_OPTIONS_H_
