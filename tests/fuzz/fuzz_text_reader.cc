// libFuzzer target: the text/CSV readers (text matrix W, CSV tables and
// points_camera.csv of a result directory) on arbitrary bytes.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/ground_truth.h"
#include "core/read_measurements.h"
#include "core/result_reader.h"
#include "core/text_io.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data,
                                      std::size_t size) {
  const std::string path = nrsfm::fuzz::WriteInputFile(data, size, ".csv");

  Eigen::MatrixXd matrix;
  if (nrsfm::ReadTextMatrix(path, &matrix).ok()) {
    if (matrix.size() == 0) std::abort();
    for (Eigen::Index i = 0; i < matrix.size(); ++i) {
      if (std::isinf(matrix.data()[i])) std::abort();
    }
  }

  nrsfm::Measurements measurements;
  if (nrsfm::ReadMeasurements(path, nrsfm::InputOptions(), &measurements)
          .ok()) {
    if (!measurements.Validate().ok()) std::abort();
  }

  Eigen::MatrixXd table;
  if (nrsfm::ReadCsvTable(path, {"frame", "point", "x"}, &table).ok()) {
    if (table.cols() != 3) std::abort();
  }

  nrsfm::GroundTruth truth;
  if (nrsfm::ReadPointsCameraCsv(path, 0, &truth).ok()) {
    for (const Eigen::Matrix3Xd& frame : truth.points_in_camera) {
      if (frame.cols() != truth.NumPoints() || !frame.allFinite())
        std::abort();
    }
  }
  return 0;
}
