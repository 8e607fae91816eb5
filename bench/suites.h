// The suites of nrsfm_bench (one file each, bench/suite_*.cc). Every suite
// prints its table(s) to stdout, writes its plots to config.output_dir and
// returns its results as JSON (the caller adds the context block and writes
// the file). A suite that cannot run (e.g. no data) says why on stdout and
// returns OK with {"skipped": "<why>"}.
#ifndef NRSFM_BENCH_SUITES_H_
#define NRSFM_BENCH_SUITES_H_

#include "bench/bench_config.h"
#include "core/model/status.h"

namespace nrsfm {
namespace bench {

// Torresani et al. 2001, Fig. 5 a/b: random bases (5, 10, 20), F = 300, K = 1 …
// N.
Status RunPaperRandomSuite(const BenchConfig& config, Json* out);
// Torresani et al. 2001, Fig. 5c: the superquadric, K = 1 … 8.
Status RunSuperquadricSuite(const BenchConfig& config, Json* out);
// Shoe-style (Table 1): K = 2 … 8, monocular and two cameras, self-occlusion.
Status RunShoeSuite(const BenchConfig& config, Json* out);
// Real motion capture: every .mat in config.datasets_dir with ground truth.
Status RunMocapSuite(const BenchConfig& config, Json* out);
// The real sequences' truth under other camera paths, noise and missing
// entries (core/synthetic/synthetic.h GenerateReprojection), against a flat
// answer and Lee et al.'s slow-rotation numbers.
Status RunRobustnessSuite(const BenchConfig& config, Json* out);
// The pinhole re-projections and the real perspective sequences
// (bench/suite_robustness.cc).
Status RunPerspectiveSuite(const BenchConfig& config, Json* out);
// Per-point covariances against the truth: calibration on random bases and
// the shoe at three noise levels, ranking on the real sequences and a slow
// orbit of each (bench/suite_uncertainty.cc).
Status RunUncertaintySuite(const BenchConfig& config, Json* out);
// Synthetic (F, P, K) sweep: time per LM iteration, total time, peak memory.
Status RunScaleSuite(const BenchConfig& config, Json* out);

}  // namespace bench
}  // namespace nrsfm

#endif  // NRSFM_BENCH_SUITES_H_
