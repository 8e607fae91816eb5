// The real sequences with ground truth of the mocap and robustness suites:
// the .mat files of --datasets_dir and the K of their published numbers.
#ifndef NRSFM_BENCH_MOCAP_DATA_H_
#define NRSFM_BENCH_MOCAP_DATA_H_

#include <string>
#include <vector>

#include "bench/bench_config.h"
#include "core/io/ground_truth.h"
#include "core/model/measurements.h"

namespace nrsfm {
namespace bench {

// A real sequence with ground truth (the mocap and robustness suites).
struct MocapSequence {
  std::string name;  // file stem
  Measurements measurements;
  GroundTruth truth;
};
// Every .mat of config.datasets_dir with measurements and ground truth,
// sorted by name, restricted to config.mocap_sequences when given. Files
// that cannot be read are skipped with a line on stdout. Returns false with
// `why` when there is no such folder or no such file.
bool LoadMocapSequences(const BenchConfig& config,
                        std::vector<MocapSequence>* sequences,
                        std::string* why);
// K of the published numbers for a sequence (drink 12, pickup 12, yoga 10,
// face 7; 8 for any other).
int PublishedNumBases(const std::string& name);

}  // namespace bench
}  // namespace nrsfm

#endif  // NRSFM_BENCH_MOCAP_DATA_H_
