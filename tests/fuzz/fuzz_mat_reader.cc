// libFuzzer target: every .mat reader (v4, v5 and v7.3 through matio/HDF5)
// on arbitrary bytes. Readers must return a Status, never crash, leak or
// read out of bounds; a successful read must satisfy the documented shapes.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/ground_truth.h"
#include "core/mat_io.h"
#include "core/read_measurements.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data,
                                      std::size_t size) {
  const std::string path = nrsfm::fuzz::WriteInputFile(data, size, ".mat");

  std::vector<std::string> names;
  (void)nrsfm::ListMatVariables(path, &names);

  Eigen::MatrixXd w;
  (void)nrsfm::ReadMatVariable(path, "W", &w);

  std::vector<Eigen::MatrixXd> slices;
  if (nrsfm::ReadMatArray3(path, "X", &slices).ok()) {
    for (const Eigen::MatrixXd& slice : slices) {
      if (slice.rows() != slices[0].rows() || slice.cols() != slices[0].cols())
        std::abort();
    }
  }

  nrsfm::Measurements measurements;
  if (nrsfm::ReadMeasurements(path, nrsfm::InputOptions(), &measurements)
          .ok()) {
    if (!measurements.Validate().ok()) std::abort();
  }

  nrsfm::GroundTruth truth;
  if (nrsfm::ReadGroundTruth(path, "", &truth).ok()) {
    for (const Eigen::Matrix3Xd& frame : truth.points_in_camera) {
      if (frame.cols() != truth.NumPoints() || !frame.allFinite())
        std::abort();
    }
  }
  return 0;
}
