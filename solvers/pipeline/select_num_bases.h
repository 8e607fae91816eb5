// Choosing K, the number of basis shapes, from the data (as Torresani et al.
// 2001 do: "K is increased until the [reprojection] error is below
// threshold").
//
// Rule. Reconstruct with K = 1 … max_num_bases. The largest K fits the data
// best; its residual, corrected for the parameters it spent, estimates the
// noise of W:
//   σ̂² = RSS(K_max) / (N − n(K_max)),     noise per coordinate,
// with N = 2 × (visible observations) scalar residuals and
//   n(K) = F·M·(3 + 2) + F·K + 3K·P + (M − 1)·F − (K² + 3)
// free parameters (rotation, translation, weights, basis, extra-camera
// scales, less the gauge: K × K basis mixing and one global rotation).
// A model with enough bases leaves a residual of the noise alone, whose RMS
// 2D distance is expected to be
//   e(K) = σ̂ · sqrt(2 (N − n(K)) / N).
// The rule keeps the smallest K with
//   rms(K) ≤ threshold · max(e(K), noise_floor),
// where noise_floor = 10⁻⁶ × (RMS spread of W) stops noise-free data from
// demanding a residual below round-off. If no K passes (e.g. every K but the
// largest is in a poor local minimum), K_max is kept.
// The largest K is reconstructed first (σ̂), then K = 1, 2, … up to the first
// that passes: the curve returned, for the caller to print, holds the K
// values tried, in increasing order. With priors =
// auto (solvers/pipeline/reconstruct.h) the curve is of the data term alone and
// the chosen K is reconstructed once more with the prior rule's terms; with
// priors = manual every K uses the given terms. Each K of the curve runs at
// most 100 LM iterations (a model with more bases than the data carry
// converges slowly along its extra freedom, and the curve needs the fit, not
// the last digits); the chosen K, if its curve solve stopped there, is
// reconstructed again with the solver's own limit.
#ifndef NRSFM_SOLVERS_PIPELINE_SELECT_NUM_BASES_H_
#define NRSFM_SOLVERS_PIPELINE_SELECT_NUM_BASES_H_

#include <vector>

#include "core/model/measurements.h"
#include "core/model/status.h"
#include "solvers/pipeline/reconstruct.h"

namespace nrsfm {

struct SelectNumBasesOptions {
  int max_num_bases = 8;   // largest K tried, ≥ 2
  double threshold = 1.1;  // factor over the expected noise RMS, ≥ 1
  Status Check() const;
};

struct NumBasesCandidate {
  int num_bases = 0;    // K
  bool ok = false;      // Reconstruct() succeeded and the refinement is usable
  std::string message;  // why not, when !ok
  double reprojection_rms = 0;  // refined, input units (RMS 2D distance)
  double expected_rms = 0;      // e(K) of the rule above
  double seconds = 0;           // wall time of this K
};

struct SelectNumBasesResult {
  int num_bases = 0;                     // the chosen K
  double noise_stddev = 0;               // σ̂, per coordinate, input units
  std::vector<NumBasesCandidate> curve;  // the K tried, increasing
  ReconstructResult reconstruction;      // of the chosen K
};

// Runs the rule. `options.start.num_bases` is ignored (set per K). Errors on
// invalid options or measurements, or when no K reconstructs at all. K values
// that the data cannot support (3K + 1 > P or > 2F) are not tried.
Status SelectNumBases(const ReconstructOptions& options,
                      const SelectNumBasesOptions& select_options,
                      const Measurements& measurements,
                      SelectNumBasesResult* result);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_PIPELINE_SELECT_NUM_BASES_H_
