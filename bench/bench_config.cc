#include "bench/bench_config.h"

#include <algorithm>

#include "problems/extra_terms.h"

namespace nrsfm {
namespace bench {

int g_max_iterations = 0;

void SetDefaultMaxIterations(int max_iterations) {
  g_max_iterations = max_iterations;
}

ReconstructOptions DefaultReconstructOptions(int num_bases, int threads) {
  ReconstructOptions options;
  if (g_max_iterations > 0) options.solver.max_iterations = g_max_iterations;
  options.start.num_bases = num_bases;
  options.solver.num_threads = std::max(1, threads);
  return options;
}

bool EnableTwoCameraRigidity(ReconstructOptions* options) {
  options->priors = PriorMode::kManual;
  options->problem.term_weights[kRigidityTerm] = kTwoCameraRigidityWeight;
  return true;
}

}  // namespace bench
}  // namespace nrsfm
