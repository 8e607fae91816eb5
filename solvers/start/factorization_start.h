// The closed-form non-rigid factorisation of Bregler, Hertzmann and
// Biermann (2000), monocular (docs/factorization.md, section 2).
//
// Input: `centered`, a one-camera Measurements whose W (2F × P) has the
// per-frame translation removed and every missing entry filled (e.g. by the
// low-rank completion); its visibility mask is not used (the factorisation
// is an SVD of the whole matrix).
//   1. SVD: W̃ ≈ Q̂ B̂, Q̂ = U D^{1/2} (2F × 3K), B̂ = D^{1/2} Vᵀ,
//      keeping the 3K largest singular values.
//   2. Sub-blocks: frame t's 2 × 3K block q_t is reordered into
//      the K × 6 matrix q̄_t (row k = [u-row, v-row] of the k-th 2 × 3
//      column block) and replaced by its rank-1 approximation σ₁ u₁ v₁ᵀ:
//      weights l̂_t = σ₁ u₁, pose block M_t = v₁ reshaped to 2 × 3. The sign
//      of each (l̂_t, M_t) pair is free; it is chosen so that every l̂_t has a
//      positive component along the principal direction of all l̂_t (a sign
//      flip of one frame would mirror its depth).
//   3. Metric upgrade (solvers/start/metric_upgrade.h) of the blocks M_t:
//      G, then per frame the nearest scaled rotation M_t G ≈ s_t Π R_t
//      (solvers/start/pose_fit.h), weights l_t = s_t l̂_t and basis S_k = G⁻¹
//      B̂_k (B̂_k rows 3k..3k+2 of B̂).
// The result is exact for K = 1 (Tomasi-Kanade) on noise-free data. For
// K > 1 it is exact only if the SVD's Q̂ happens to be Q (C ⊗ G⁻¹)-shaped;
// in general Q̂ = Q A for an arbitrary invertible 3K × 3K A, the reordered
// blocks are not rank 1 and step 2 throws information away (Torresani et al.
// 2001: "bad rank-1 approximations, and bad estimates for R_t").
// `mean_subblock_rank1_defect` measures this.
#ifndef NRSFM_SOLVERS_START_FACTORIZATION_START_H_
#define NRSFM_SOLVERS_START_FACTORIZATION_START_H_

#include "core/math/svd.h"
#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"

namespace nrsfm {

struct FactorizationStartSummary {
  // see solvers/start/metric_upgrade.h
  bool metric_upgrade_was_indefinite = false;
  // Mean over frames of σ₂/σ₁ of q̄_t: 0 when every reordered block is
  // exactly rank 1, larger the more step 2 discards.
  double mean_subblock_rank1_defect = 0.0;
};

// Fills `model` (Resize'd to F, 1, P, K; zero translations, unit scales).
// Errors when 3K exceeds 2F or P − 1, when the centred tracks have rank < 3
// (σ₃ < 1e-6 σ₁: no rotation, or a flat object), or when the metric upgrade
// fails (too little rotation). `svd`: StartSvd(centered.W, K)
// (solvers/start/metric_upgrade.h) when the caller has it, else null and it is
// computed here.
Status FactorizationStart(const Measurements& centered, int num_bases,
                          Model* model, FactorizationStartSummary* summary,
                          const ThinSvd* svd = nullptr);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_START_FACTORIZATION_START_H_
