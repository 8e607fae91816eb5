// libFuzzer target: the observation-list reader ("frame camera point u v")
// on arbitrary bytes, directly and through ReadMeasurements.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/io/read_measurements.h"
#include "core/io/text_io.h"
#include "tests/fuzz/allocation_budget.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data,
                                      std::size_t size) {
  const nrsfm::fuzz::AllocationBudget budget(size);
  const std::string path = nrsfm::fuzz::WriteInputFile(data, size, ".obs");

  nrsfm::Measurements measurements;
  if (nrsfm::ReadObservationList(path, &measurements).ok()) {
    if (!measurements.Validate().ok()) std::abort();
    if (measurements.NumVisible() < 1) std::abort();
  }
  nrsfm::InputOptions options;
  options.num_cameras = 2;
  if (nrsfm::ReadMeasurements(path, options, &measurements).ok()) {
    if (!measurements.Validate().ok() || measurements.num_cameras != 2)
      std::abort();
  }
  return 0;
}
