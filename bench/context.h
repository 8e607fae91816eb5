// The "context" block of nrsfm_bench's results.json: the machine and build
// a run's numbers come from.
#ifndef NRSFM_BENCH_CONTEXT_H_
#define NRSFM_BENCH_CONTEXT_H_

#include "bench/bench_config.h"

namespace nrsfm {
namespace bench {

// Date, host, cores, threads, compiler, Ceres/Eigen versions, BLAS/LAPACK.
Json ContextBlock(int threads);

}  // namespace bench
}  // namespace nrsfm

#endif  // NRSFM_BENCH_CONTEXT_H_
