// Closed-form initialisation of the NRSfM model (DESIGN.md §3; 000 §3,
// 001 §3.3, §3.4.1-3.4.3), the start of the Ceres refinement.
//
// Pipeline:
//   1. Missing entries (if any): rank-(3K + 1) affine low-rank completion of
//      the whole 2FM × P matrix (solvers/low_rank_completion.h).
//   2. Translation T_tc: the 2D mean of view (t, c) when it sees every point
//      (Tomasi-Kanade centring), otherwise the affine term of the completion.
//      The starts work on W̃ = completed W − T (camera 0's rows).
//   3. Start(s) on camera 0:
//        factorization — rank-3K SVD, per-frame rank-1 sub-block
//                        factorisation, metric upgrade (000 §3;
//                        solvers/factorization_start.h);
//        rigid         — rank-3 Tomasi-Kanade + metric upgrade, then weights
//                        and basis by least squares alternated with rotation
//                        updates (001 §3.4.2; solvers/rigid_start.h);
//        triple        — the rigid start's steps 2-3 from the rotations of
//                        the rank-3K corrective triple (orthonormality
//                        constraints; solvers/corrective_triple.h);
//        auto          — factorization and rigid; keeps the one with the lower reprojection RMS
//                        (a start that fails is skipped with a warning).
//   4. M > 1: cameras c ≥ 1 posed against camera 0's shapes, the depth
//      reflection chosen by them, rig rotation / scale estimated
//      (solvers/multi_camera_start.h).
// The model follows core/model.h: monocular s = 1 (projection scale in l_t);
// with M > 1 camera 0 has s = 1 and cameras c ≥ 1 their own s_tc.
// Gauges left as they fall: global rotation (from the symmetric G = H^{1/2}),
// depth reflection (arbitrary, also with M > 1: orthographic cameras do not
// fix it), K × K basis mixing.
//
// "No rotation in the sequence" is detected when the centred tracks of
// camera 0 have rank < 3 (σ₃ < 1e-6 σ₁: a rigid object that does not
// rotate, or a flat one) or when the orthonormality equations of the metric
// upgrade leave H undetermined (solvers/metric_upgrade.h). A deforming object
// seen without rotation has tracks of rank up to 2K that look like a
// rotating object's; it is not detected (the start explains part of the
// deformation as rotation). Noise also hides the rank test.
#ifndef NRSFM_SOLVERS_INITIALIZE_H_
#define NRSFM_SOLVERS_INITIALIZE_H_

#include <cstdint>
#include <string>
#include <vector>

#include "core/measurements.h"
#include "core/model.h"
#include "core/status.h"

namespace nrsfm {

enum class StartMethod { kAuto, kFactorization, kRigid, kTriple };

// "auto" | "factorization" | "rigid" | "triple".
const char* StartMethodName(StartMethod m);
// Parses one of the names above; the error lists the valid names.
Status ParseStartMethod(const std::string& s, StartMethod* m);

struct StartOptions {
  StartMethod method = StartMethod::kAuto;
  int num_bases = 1;                    // K ≥ 1
  int completion_max_iterations = 500;  // alternations of the low-rank completion, ≥ 1
  double completion_tolerance = 1e-12;  // relative change of the fit residual to stop, ≥ 0
  int rigid_refine_iterations = 20;     // alternations (basis, weights, rotations) of the rigid start (001 §3.4.2), 0 = none
  double rigid_initial_deformation = 0.01;  // std of the random initial weights of bases 2..K (rigid start), ≥ 0
  std::uint64_t seed = 1;               // for the rigid start's random weights (mt19937_64 + own Box-Muller)

  Status Check() const;
};

struct StartSummary {
  StartMethod used = StartMethod::kFactorization;  // the start that was kept
  double reprojection_rms = 0;                   // of the kept start (RMS 2-D distance over visible entries, input units)
  double factorization_rms = -1, rigid_rms = -1; // -1 = not run (or failed)
  double completion_rms = -1;                    // fit residual RMS of the low-rank completion on visible entries, -1 if data complete
  int completion_iterations = 0;
  bool metric_upgrade_was_indefinite = false;    // kept start: H had an eigenvalue clamped (solvers/metric_upgrade.h)
  // Triple start: segments of frames with one rotation sign (1 = every frame
  // linked in time; F = one decision per frame; solvers/corrective_triple.h);
  // -1 when the kept start is not the triple. 1 < segments < F adds a warning.
  int triple_sign_segments = -1;
  std::vector<std::string> warnings;
  double seconds = 0;                            // wall time of Initialize
};

// Fills `model` (Resize'd to F, M, P, K): rotations (angle-axis),
// translations, weights, basis, scales (camera 0 scale 1; with M > 1 the
// extra cameras' scales and rig_rotations / rig_scales estimated).
// Errors (never NaN output) on invalid options or measurements, F < 2,
// P < 3K + 1 or 2F < 3K + 1, a view or point with no visible entry (named),
// a view with fewer than 3K + 1 visible points or a point seen in fewer than
// ⌈3K / 2⌉ views when entries are missing, tracks with no rotation (rank < 3,
// or orthonormality equations that do not determine the metric), and when
// every selected start fails.
Status Initialize(const StartOptions& options,
                  const Measurements& measurements, Model* model,
                  StartSummary* summary);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_INITIALIZE_H_
