#include "bench/k_sweep.h"

#include "bench/report.h"
#include "bench/run_evaluate.h"
#include "core/math/parallel_for.h"

namespace nrsfm {
namespace bench {

SweepResult SweepK(
    const std::function<Status(std::uint64_t seed, SyntheticSequence*)>& make,
    const std::vector<int>& ks, int runs,
    const std::function<ReconstructOptions(int num_bases)>& options, int jobs) {
  SweepResult sweep;
  std::vector<SyntheticSequence> sequences(runs);
  std::vector<Status> made(runs);
  for (int r = 0; r < runs; ++r) {
    made[r] = make(static_cast<std::uint64_t>(r + 1), &sequences[r]);
  }
  // Outcome of K = ks[i], run r at index i * runs + r.
  std::vector<RunOutcome> outcomes(ks.size() * runs);
  ParallelFor(static_cast<int>(outcomes.size()), jobs, /*grain=*/1,
              [&](int begin, int end) {
                for (int index = begin; index < end; ++index) {
                  const int k = ks[index / runs];
                  const int r = index % runs;
                  RunOutcome& o = outcomes[index];
                  if (made[r].ok()) {
                    o = ReconstructAndEvaluate(options(k),
                                               sequences[r].measurements,
                                               TruthShapes(sequences[r].truth));
                    // The model is not needed here; dropping it keeps the
                    // sweep's memory small.
                    o.model = Model();
                  } else {
                    o.message = made[r].message();
                  }
                }
              });
  for (size_t i = 0; i < ks.size(); ++i) {
    const int k = ks[i];
    SweepPoint point;
    point.num_bases = k;
    std::vector<double> e3d_pct, z_pct, e3d, seconds;
    for (int r = 0; r < runs; ++r) {
      const RunOutcome& o = outcomes[i * runs + r];
      Json j;
      j["num_bases"] = k;
      j["seed"] = r + 1;
      j["ok"] = o.ok;
      if (!o.message.empty()) j["message"] = o.message;
      AddMetrics(o.errors, &j);
      j["reprojection_rms"] = o.reprojection_rms;
      j["start"] = o.start;
      j["iterations"] = o.iterations;
      j["total_seconds"] = o.total_seconds;
      sweep.runs.push_back(j);
      if (!o.ok) {
        ++point.failures;
        continue;
      }
      e3d_pct.push_back(o.errors.error3d_pct);
      z_pct.push_back(o.errors.zerror_pct);
      e3d.push_back(o.errors.e3d);
      seconds.push_back(o.total_seconds);
    }
    point.median_error3d_pct = Median(e3d_pct);
    point.median_zerror_pct = Median(z_pct);
    point.median_e3d = Median(e3d);
    point.median_seconds = Median(seconds);
    sweep.points.push_back(point);
  }
  return sweep;
}

}  // namespace bench
}  // namespace nrsfm
