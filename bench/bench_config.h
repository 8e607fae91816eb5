// What every nrsfm_bench suite reads (bench/suite_*.cc): the run
// configuration from the flags of bench/nrsfm_bench.cc, the JSON type the
// suites return, and the reconstruction options they start from.
#ifndef NRSFM_BENCH_BENCH_CONFIG_H_
#define NRSFM_BENCH_BENCH_CONFIG_H_

#include <nlohmann/json.hpp>
#include <string>

#include "solvers/pipeline/reconstruct.h"

namespace nrsfm {
namespace bench {

using Json = nlohmann::ordered_json;

// What every suite reads (from the gflags of bench/nrsfm_bench.cc).
struct BenchConfig {
  bool full = false;  // the paper-sized run (e.g. R = 30) instead of the
                      // reduced default
  // the default run of every suite (--suite=default): smaller still
  bool quick = false;
  int runs = 0;  // R, random runs per setting; 0 = the suite's default
  std::string datasets_dir;     // folder with the mocap .mat files ("" = none)
  std::string output_dir;       // JSON and plots go here
  int threads = 1;              // Ceres threads
  bool plots = true;            // write plots when gnuplot is available
  std::string mocap_sequences;  // comma-separated file stems to run ("" = all)
  // wall-time cap of each shoe and mocap refinement, 0 = none
  double max_seconds = 0;
  int jobs = 1;  // reconstructions run at once (the scale suite: always 1)
  // mocap: default | plain | triple, ts joined by '+' | all
  std::string strategy = "default";
};

// The options every suite uses unless it says otherwise: Reconstruct()'s
// defaults with K and the thread count set.
// (--max_iterations > 0 replaces the LM iteration limit; set once by main
// through SetDefaultMaxIterations.)
ReconstructOptions DefaultReconstructOptions(int num_bases, int threads);
void SetDefaultMaxIterations(int max_iterations);

// The one place that decides how "second camera + rigidity" runs: the
// multi-camera rigidity term (problems/rigidity_error.h) with
// weight kTwoCameraRigidityWeight, the value of the CLI's two-camera shoe
// test (tests/tools/cli_test.cc, ExtraTermFlags). Returns true (the shoe
// table's column header says whether the term ran).
constexpr double kTwoCameraRigidityWeight = 100.0;
bool EnableTwoCameraRigidity(ReconstructOptions* options);

}  // namespace bench
}  // namespace nrsfm

#endif  // NRSFM_BENCH_BENCH_CONFIG_H_
