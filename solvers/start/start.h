// The closed-form start of the refinement (docs/factorization.md): one named
// start, computed from the measurements. Which start a reconstruction uses
// is Reconstruct()'s choice (solvers/pipeline/reconstruct.h); ComputeStart()
// runs the one it is given.
//
// Pipeline:
//   1. Missing entries (if any): rank-3K affine low-rank completion of the
//      whole 2FM × P matrix (solvers/start/low_rank_completion.h).
//   2. Translation T_tc: the 2D mean of view (t, c) when it sees every point
//      (Tomasi-Kanade centring), otherwise the affine term of the completion.
//      The start works on W̃ = completed W − T (camera 0's rows).
//   3. The start on camera 0, one function per file:
//        factorization — Bregler's rank-3K SVD, per-frame rank-1 sub-blocks
//                        and metric upgrade
//                        (solvers/start/factorization_start.h);
//        rigid         — Tomasi-Kanade rotations, then the basis / weights /
//                        rotations alternation (solvers/start/rigid_start.h);
//        triple        — the rotations of the rank-3K corrective triple, then
//                        the basis / weights alternation
//                        (solvers/start/triple_start.h).
//   4. M > 1: cameras c ≥ 1 posed against camera 0's shapes, rig rotation /
//      scale estimated (solvers/start/multi_camera_start.h).
// The model follows core/model/model.h: monocular s = 1 (projection scale in
// l_t); with M > 1 camera 0 has s = 1 and cameras c ≥ 1 their own s_tc. Gauges
// are left as they fall (docs/model.md).
//
// "No rotation in the sequence" is detected when the centred tracks of
// camera 0 have rank < 3 (σ₃ < 1e-6 σ₁: a rigid object that does not
// rotate, or a flat one) or when the orthonormality equations of the metric
// upgrade leave H undetermined (solvers/start/metric_upgrade.h). A deforming
// object seen without rotation has tracks of rank up to 2K that look like a
// rotating object's; it is not detected (the start explains part of the
// deformation as rotation). Noise also hides the rank test.
#ifndef NRSFM_SOLVERS_START_START_H_
#define NRSFM_SOLVERS_START_START_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "core/math/svd.h"
#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"
#include "solvers/start/alternation.h"
#include "solvers/start/low_rank_completion.h"

namespace nrsfm {

// kAuto is Reconstruct()'s rule (solvers/pipeline/reconstruct.h), not a start.
enum class StartMethod { kAuto, kFactorization, kRigid, kTriple };

// "auto" | "factorization" | "rigid" | "triple"; the error lists them.
const char* StartMethodName(StartMethod method);
Status ParseStartMethod(const std::string& name, StartMethod* method);

struct StartOptions {
  // ComputeStart() needs a named start
  StartMethod method = StartMethod::kAuto;
  int num_bases = 1;                    // K ≥ 1
  LowRankCompletionOptions completion;  // step 1 (its rank is 3K)
  AlternationOptions alternation;       // the rigid and triple starts
  std::uint64_t seed = 1;  // random initial weights (rigid, triple) and the
                           // triple's random starts

  Status Check() const;
};

struct StartSummary {
  StartMethod method = StartMethod::kFactorization;  // the start computed
  // RMS 2-D distance over visible entries, input units
  double reprojection_rms = 0;
  double completion_rms = -1;  // fit residual RMS of the low-rank completion on
                               // visible entries, -1 if data complete
  // Factorization start: mean σ₂/σ₁ of the reordered per-frame blocks, how
  // much its rank-1 step discards (solvers/start/factorization_start.h); -1 for
  // the other starts.
  double subblock_rank1_defect = -1;
  // Rigid and triple starts: RMS over camera 0's visible entries of the rigid
  // model the alternation starts from (solvers/start/alternation.h), input
  // units; -1 for the factorization start.
  double rigid_rms = -1;
  // Triple start: segments of frames with one rotation sign (1 = every frame
  // linked in time; F = one decision per frame;
  // solvers/start/corrective_triple.h); -1 for the other starts. 1 < segments <
  // F adds a warning.
  int triple_sign_segments = -1;
  // A start with fewer bases than K, a triple start split into sign
  // segments, a metric upgrade whose H was clamped (the depth is unreliable).
  std::vector<std::string> warnings;
  double seconds = 0;  // wall time of ComputeStart
};

// Work the starts of one set of measurements share, each piece computed
// once: the low-rank completions of step 1 (also the prior rule's,
// solvers/pipeline/prior_rule.h) and the thin SVD of camera 0's centred tracks
// that the factorization and rigid starts begin with (ComputeTopSvd: its top
// 3K' singular values and vectors, one entry per 3K'). Reconstruct() keeps one
// for its prior rule and its starts; the starts it gives are the same, bit for
// bit, as without it. Safe to use from several threads. `measurements` must
// outlive it, and it may only be given to ComputeStart() with these
// measurements. The completions run on up to `num_threads` threads (the result
// does not depend on it).
class StartCache {
 public:
  explicit StartCache(const Measurements& measurements, int num_threads = 1)
      : measurements_(measurements), completions_(measurements, num_threads) {}
  StartCache(const StartCache&) = delete;
  StartCache& operator=(const StartCache&) = delete;

  const Measurements& measurements() const { return measurements_; }
  LowRankCompletionMemo& completions() { return completions_; }

  // The SVD stored under `key` (the completion the centred tracks came
  // from), computed by `compute` the first time it is asked for.
  std::shared_ptr<const ThinSvd> Svd(const std::string& key,
                                     const std::function<ThinSvd()>& compute);

 private:
  const Measurements& measurements_;
  LowRankCompletionMemo completions_;
  std::mutex mutex_;
  std::vector<std::pair<std::string, std::shared_ptr<const ThinSvd>>> svds_;
};

// Fills `model` (Resize'd to F, M, P, K) with the start options.method:
// rotations (angle-axis), translations, weights, basis, scales (camera 0
// scale 1; with M > 1 the extra cameras' scales and rig_rotations /
// rig_scales estimated). Errors (never NaN output) on invalid options, on
// method = auto, on invalid measurements, F < 2, P < 3K + 1 or 2F < 3K + 1,
// a view or point with no visible entry (named), a view with fewer than
// 4 visible points or a point seen in fewer than 2 views when entries are
// missing (what K' = 1 needs), tracks with no rotation (rank < 3, or
// orthonormality equations that do not determine the metric), and when the
// start fails.
// Missing entries: the rank-3K completion needs every view to see 3K + 1
// points and every point to be seen in ⌈3K / 2⌉ views. When they allow only
// K' < K, the start is computed with K' bases and extended by K − K' zero
// basis shapes whose weights are small (1 % of the start's RMS weight,
// seeded), for the refinement to fit; summary->warnings says so.
// The parts of a start that run in parallel (the corrective triple's
// starts) use up to `num_threads` threads; the start does not depend on it.
// `cache` (for these measurements, or null) holds work shared with other
// starts; it does not change the start.
Status ComputeStart(const StartOptions& options,
                    const Measurements& measurements, Model* model,
                    StartSummary* summary, int num_threads = 1,
                    StartCache* cache = nullptr);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_START_START_H_
