// Extends a monocular start of camera 0 to M synchronised cameras
// (docs/factorization.md, section 6): the cameras of one frame share the
// weights l_t, so the object-frame shape S_t of camera 0's model is the shape
// every camera sees, w_tcp = s_tc Π R_tc S_t[:, p] (centred).
//   1. Per view (t, c ≥ 1) with at least 4 visible points that span 3D:
//      s_tc, R_tc by FitWeakPerspectivePose (solvers/start/pose_fit.h) of its
//      visible centred 2D points to S_t.
//   2. Rig: R_c = NearestRotation(Σ_t R_tc R_t0ᵀ) (the chordal L2 mean of
//      the relative rotations), rig scale = mean_t s_tc (camera 0 has s = 1).
//      Views step 1 could not fit get R_tc = R_c R_t0 and s_tc = rig scale.
// Orthographic cameras, however many, do not fix the global depth
// reflection: (R_tc → D R_tc D, S_k → D S_k, D = diag(1, 1, −1)) leaves every
// image unchanged and maps the rig rotation R_c to D R_c D. The rig is
// therefore returned in the reflection of camera 0's start; compare with a
// ground truth up to that reflection.
#ifndef NRSFM_SOLVERS_START_MULTI_CAMERA_START_H_
#define NRSFM_SOLVERS_START_MULTI_CAMERA_START_H_

#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"

namespace nrsfm {

// `centered`: all M cameras, W with the per-view translation removed (only
// visible entries are used). `camera0`: a monocular model (F, 1, P, K) of
// camera 0's rows. Fills `model` (Resize'd to F, M, P, K; zero
// translations). Errors when a camera c ≥ 1 has no view that step 1 can fit.
Status ExtendToCameras(const Measurements& centered, const Model& camera0,
                       Model* model);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_START_MULTI_CAMERA_START_H_
