// The perspective camera's "iterative extension" of the weak-perspective
// answer (Torresani et al. 2001 §3.1; docs/camera.md): the weak-perspective
// model read as a pinhole model of the same images, then refined in the one
// Ceres problem with the pinhole data term (problems/perspective_error.h)
// and the same extra terms.
#ifndef NRSFM_SOLVERS_PIPELINE_PERSPECTIVE_H_
#define NRSFM_SOLVERS_PIPELINE_PERSPECTIVE_H_

#include <Eigen/Core>

#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"
#include "problems/problem_options.h"
#include "solvers/refine/refine.h"
#include "solvers/refine/solver_options.h"

namespace nrsfm {

// The pinhole model whose images are, to first order in depth/distance,
// those of the weak-perspective `weak` (no left-out frames): view (t, c) at
// depth t_z = fx_c / s_tc (so frame t's shape keeps its size, in units where
// camera 0 sees depth fx_0 at scale 1), T = (w̄ − c) t_z / f, scales 1;
// with `reflect`, the depth-reflected answer weak perspective cannot tell
// apart (R → Z R Z, S_k → Z S_k, Z = diag(1, 1, −1)). `intrinsics` 4 × M.
Model PerspectiveFromWeak(const Model& weak, const Eigen::Matrix4Xd& intrinsics,
                          bool reflect);

// Refines both readings of `weak` (as is and depth-reflected) under the
// pinhole camera of `measurements.intrinsics` with `problem`'s terms and
// keeps the lower final cost. Errors when the measurements have no
// intrinsics or neither refinement is usable.
Status RefinePerspective(const ProblemOptions& problem,
                         const SolverOptions& solver,
                         const Measurements& measurements, const Model& weak,
                         Model* model, RefineSummary* summary);

// Multiplies the shapes and translations of a perspective model by one
// factor so that the mean depth of the first frame's camera-0 points (its
// finite ones) is `depth` > 0; every image is unchanged. Returns false (and
// changes nothing) when that mean depth is not positive.
bool SetMeanDepth(double depth, Model* model);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_PIPELINE_PERSPECTIVE_H_
