#include "solvers/pipeline/select_num_bases.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <utility>

#include "core/model/option_checker.h"

namespace nrsfm {
namespace {

// The floor of e(K) in the rule of the header, times the RMS spread of W
// (dimensionless): far above round-off, far below any real noise.
constexpr double kRelativeNoiseFloor = 1e-6;
// LM iterations of each K of the curve (at most the solver's own limit); the
// chosen K is reconstructed again with the solver's limit.
constexpr int kCurveMaxIterations = 100;

// Free parameters of a model with K bases, less the gauge (see the header).
double NumFreeParameters(const Measurements& m, int k) {
  const double f = m.num_frames, views = m.NumViews(), p = m.num_points;
  return views * 5.0 + f * k + 3.0 * k * p + (m.num_cameras - 1) * f -
         (static_cast<double>(k) * k + 3.0);
}

}  // namespace

Status SelectNumBasesOptions::Check() const {
  OptionChecker check("K selection");
  check.AtLeast("max_num_bases", max_num_bases, 2);
  check.FiniteAtLeast("threshold", threshold, 1.0);
  return check.status();
}

Status SelectNumBases(const ReconstructOptions& options,
                      const SelectNumBasesOptions& select_options,
                      const Measurements& measurements,
                      SelectNumBasesResult* result) {
  NRSFM_RETURN_IF_ERROR(select_options.Check());
  NRSFM_RETURN_IF_ERROR(measurements.Validate());
  const int num_observations = measurements.NumVisible();
  // The largest K the data supports: 3K + 1 ≤ P and 3K + 1 ≤ 2F, and more
  // scalar residuals than free parameters.
  int k_max = select_options.max_num_bases;
  while (k_max >= 1 &&
         (3 * k_max + 1 > measurements.num_points ||
          3 * k_max + 1 > 2 * measurements.num_frames ||
          NumFreeParameters(measurements, k_max) >= 2.0 * num_observations)) {
    --k_max;
  }
  if (k_max < 1) {
    return Status::Error("K selection: the data supports no K >= 1 (P = " +
                         std::to_string(measurements.num_points) + ", F = " +
                         std::to_string(measurements.num_frames) + ")");
  }

  SelectNumBasesResult out;
  // One point of the curve: K reconstructed, its reprojection RMS.
  const auto curve_point = [&](int k, ReconstructResult* reconstruction) {
    ReconstructOptions k_options = options;
    k_options.start.num_bases = k;
    // The curve measures how well K bases fit the tracks: with priors = auto
    // it is the data term alone (the chosen K is then reconstructed with the
    // rule's terms); manual terms are kept as given.
    if (options.priors == PriorMode::kAuto) {
      k_options.priors = PriorMode::kManual;
      k_options.problem.term_weights.clear();
    }
    // Each point of the curve needs the fit, not the last digits: models
    // with more bases than the data carry converge slowly along their extra
    // freedom.
    k_options.solver.max_iterations =
        std::min(options.solver.max_iterations, kCurveMaxIterations);
    NumBasesCandidate candidate;
    candidate.num_bases = k;
    const Status status = Reconstruct(k_options, measurements, reconstruction);
    if (!status.ok()) {
      candidate.message = status.message();
    } else if (!reconstruction->refine.usable) {
      candidate.message =
          "refinement not usable: " + reconstruction->refine.message;
    } else {
      candidate.ok = true;
      candidate.reprojection_rms = reconstruction->refine.reprojection_rms;
      candidate.seconds = reconstruction->total_seconds;
    }
    return candidate;
  };

  // σ̂ from the best-fitting (largest successful) K, tried first: the rule
  // keeps the smallest K that passes, so the curve below it stops there.
  std::map<int, NumBasesCandidate> tried;
  std::map<int, ReconstructResult> reconstructions;
  int reference = -1;
  for (int k = k_max; k >= 1 && reference < 0; --k) {
    tried[k] = curve_point(k, &reconstructions[k]);
    if (tried[k].ok) reference = k;
  }
  if (reference < 0) {
    return Status::Error("K selection: no K in 1.." + std::to_string(k_max) +
                         " reconstructed; K = 1: " + tried[1].message);
  }
  const double n_obs = 2.0 * num_observations;
  const double rss =
      n_obs * 0.5 * std::pow(tried[reference].reprojection_rms, 2);
  const double dof = n_obs - NumFreeParameters(measurements, reference);
  out.noise_stddev = std::sqrt(rss / std::max(dof, 1.0));
  const double floor = kRelativeNoiseFloor * measurements.ImageSpreadRms();
  const auto expected_rms = [&](int k) {
    const double dof_k = n_obs - NumFreeParameters(measurements, k);
    return out.noise_stddev * std::sqrt(2.0 * std::max(dof_k, 0.0) / n_obs);
  };
  const auto passes = [&](const NumBasesCandidate& candidate) {
    return candidate.ok && candidate.reprojection_rms <=
                               select_options.threshold *
                                   std::max(candidate.expected_rms, floor);
  };
  out.num_bases = reference;
  for (int k = 1; k <= reference; ++k) {
    if (tried.count(k) == 0) tried[k] = curve_point(k, &reconstructions[k]);
    tried[k].expected_rms = expected_rms(k);
    if (passes(tried[k])) {
      out.num_bases = k;
      break;
    }
  }
  for (auto& [k, candidate] : tried) {
    candidate.expected_rms = expected_rms(k);
    out.curve.push_back(candidate);
  }
  // The chosen K once more with the solver's own iteration limit (and, with
  // priors = auto, the rule's terms), unless its curve solve already had both.
  const ReconstructResult& curve_result = reconstructions[out.num_bases];
  if (options.priors == PriorMode::kAuto ||
      (curve_result.refine.usable && !curve_result.refine.converged &&
       kCurveMaxIterations < options.solver.max_iterations)) {
    ReconstructOptions chosen = options;
    chosen.start.num_bases = out.num_bases;
    NRSFM_RETURN_IF_ERROR(
        Reconstruct(chosen, measurements, &out.reconstruction)
            .WithContext("K = " + std::to_string(out.num_bases)));
  } else {
    out.reconstruction = std::move(reconstructions[out.num_bases]);
  }
  *result = std::move(out);
  return Status::OK();
}

}  // namespace nrsfm
