// The K sweep of the synthetic suites (paper-random, superquadric, shoe):
// each K and each random run reconstructed and scored, medians over the runs.
#ifndef NRSFM_BENCH_K_SWEEP_H_
#define NRSFM_BENCH_K_SWEEP_H_

#include <cstdint>
#include <functional>
#include <vector>

#include "bench/bench_config.h"
#include "core/model/status.h"
#include "core/synthetic/synthetic.h"
#include "solvers/pipeline/reconstruct.h"

namespace nrsfm {
namespace bench {

// K sweep on synthetic data: for each K and each run r = 0 … runs − 1,
// make(seed = r + 1) generates a sequence, options(K) reconstructs it, and
// the errors against its truth are collected. Medians over the runs (failed
// runs excluded and counted).
struct SweepPoint {
  int num_bases = 0;
  int failures = 0;
  double median_error3d_pct = 0, median_zerror_pct = 0, median_e3d = 0;
  double median_seconds = 0;
};
struct SweepResult {
  std::vector<SweepPoint> points;
  Json runs = Json::array();  // every run
};
// The (K, run) reconstructions run `jobs` at a time (core/math/parallel_for.h);
// results are collected in order, so the output does not depend on `jobs`
// (the times do: runs that share the machine take longer).
SweepResult SweepK(
    const std::function<Status(std::uint64_t seed, SyntheticSequence*)>& make,
    const std::vector<int>& ks, int runs,
    const std::function<ReconstructOptions(int num_bases)>& options, int jobs);

}  // namespace bench
}  // namespace nrsfm

#endif  // NRSFM_BENCH_K_SWEEP_H_
