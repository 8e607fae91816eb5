// The corrective-triple start, monocular: the rotations of the rank-3K
// factorisation's corrective triple (solvers/start/corrective_triple.h), then
// the basis/weights alternation of solvers/start/alternation.h with those
// rotations held (they are exact on noise-free data; updates against a
// still-wrong basis would only move them away). docs/factorization.md.
//
// Input: `centered`, a one-camera Measurements whose W (2F × P) has the
// per-frame translation removed and every missing entry filled; its
// visibility mask says which entries are real.
#ifndef NRSFM_SOLVERS_START_TRIPLE_START_H_
#define NRSFM_SOLVERS_START_TRIPLE_START_H_

#include <cstdint>

#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"
#include "solvers/start/alternation.h"
#include "solvers/start/corrective_triple.h"

namespace nrsfm {

struct TripleStartSummary {
  CorrectiveTripleSummary triple;  // how the rotation signs were chosen
  AlternationSummary alternation;  // RMS of the rigid and the returned model
};

// Fills `model` (Resize'd to F, 1, P, K; unit scales; translations = δT, to
// be added to the translations removed from `centered`); `seed` seeds the
// triple's random starts and the random initial weights; the triple's starts
// run on up to `num_threads` threads (the result does not depend on it). Errors
// on invalid options, when K < 1, 3 > 2F or P < 4, when 3K exceeds 2F or P, or
// when the tracks have rank < 3.
Status TripleStart(const Measurements& centered, int num_bases,
                   const AlternationOptions& options, std::uint64_t seed,
                   int num_threads, Model* model, TripleStartSummary* summary);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_START_TRIPLE_START_H_
