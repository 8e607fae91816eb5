// Time and memory of the nrsfm_bench runs: a steady clock, and a piece of
// work run in a forked child so that its peak memory is its own.
#ifndef NRSFM_BENCH_MEASURE_H_
#define NRSFM_BENCH_MEASURE_H_

#include <functional>
#include <string>

#include "bench/bench_config.h"

namespace nrsfm {
namespace bench {

// Runs `work` in a forked child and measures its memory. The child's peak
// resident set (VmHWM) starts at the RSS it inherits, so both are reported.
// `work` returns a JSON object that is passed back through a pipe.
struct ChildResult {
  bool ok = false;
  std::string message;
  double start_rss_mb = 0;  // RSS when the child started (inherited pages)
  double peak_rss_mb = 0;   // VmHWM at the end of the child
  Json payload;
};
ChildResult RunInChild(const std::function<Json()>& work);

// Seconds since an arbitrary epoch (steady clock).
double NowSeconds();

}  // namespace bench
}  // namespace nrsfm

#endif  // NRSFM_BENCH_MEASURE_H_
