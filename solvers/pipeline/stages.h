// The stages of Reconstruct() (solvers/pipeline/reconstruct.h) with the
// terms decided: a start and its refinement, and the camera and shape
// stages. Reconstruct() decides the terms, repairs and scales around them.
#ifndef NRSFM_SOLVERS_PIPELINE_STAGES_H_
#define NRSFM_SOLVERS_PIPELINE_STAGES_H_

#include "core/model/measurements.h"
#include "core/model/status.h"
#include "solvers/pipeline/prior_rule.h"
#include "solvers/pipeline/reconstruct.h"
#include "solvers/refine/refine.h"
#include "solvers/start/start.h"

namespace nrsfm {

// One start (method) followed by its refinement. With priors = auto the
// start decides the path prior and the temporal weights (DecideStartPriors,
// `decision` holding the rule's other facts, `strength` multiplying the
// shape prior), and the full priors are compared with their alternative
// (solvers/pipeline/prior_comparison.h). `cache` holds the work the starts
// share (solvers/start/start.h); `kept`, when not null, the refinement's
// problem for the next start's (solvers/refine/refine.h, KeptProblem).
Status StartAndRefine(const ReconstructOptions& options, StartMethod method,
                      const Measurements& measurements,
                      const PriorDecision& decision, double strength,
                      StartCache* cache, ReconstructResult* result,
                      KeptProblem* kept);

// The camera stage and, with K_cam > K, the shape stage, with the rule's
// decision `rule` (priors = auto) or the caller's terms; `strength`
// multiplies the shape prior (DecideStartPriors) and, above 1, adds it when
// the rule had none.
Status SolveWithPriors(const ReconstructOptions& options,
                       const Measurements& measurements,
                       const PriorDecision& rule, double strength,
                       StartCache* cache, ReconstructResult* result);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_PIPELINE_STAGES_H_
