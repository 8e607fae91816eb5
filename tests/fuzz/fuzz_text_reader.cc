// libFuzzer target: the text/CSV readers (text matrix W, CSV tables,
// points_camera.csv and a whole result directory) on arbitrary bytes. For
// the directory the input is split at form feeds into points_camera.csv,
// points_object.csv and rotations.csv (fuzz_input_file.h).
#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/io/ground_truth.h"
#include "core/io/read_measurements.h"
#include "core/io/result_reader.h"
#include "core/io/text_io.h"
#include "tests/fuzz/allocation_budget.h"
#include "tests/fuzz/fuzz_input_file.h"

namespace {

// Every point finite, or all three coordinates NaN (a point or frame left
// out of a reconstruction).
bool PointsFiniteOrLeftOut(const Eigen::Matrix3Xd& points) {
  for (Eigen::Index p = 0; p < points.cols(); ++p) {
    if (!points.col(p).allFinite() && !points.col(p).array().isNaN().all())
      return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data,
                                      std::size_t size) {
  const nrsfm::fuzz::AllocationBudget budget(size);
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
    if (truth.NumFrames() < 1 || truth.NumPoints() < 1) std::abort();
    for (const Eigen::Matrix3Xd& frame : truth.points_in_camera) {
      if (frame.cols() != truth.NumPoints() || !PointsFiniteOrLeftOut(frame))
        std::abort();
    }
  }

  const std::string dir = nrsfm::fuzz::WriteInputDirectory(
      data, size, {"points_camera.csv", "points_object.csv", "rotations.csv"});
  nrsfm::GroundTruth shapes;
  if (nrsfm::ReadResultShapes(dir, 0, &shapes).ok()) {
    if (shapes.NumFrames() < 1 || shapes.NumPoints() < 1 ||
        !shapes.HasObjectFrame())
      std::abort();
    for (int t = 0; t < shapes.NumFrames(); ++t) {
      // A rotation, or all NaN for a frame left out.
      const Eigen::Matrix3d& r = shapes.rotations[t];
      const bool rotation_ok = r.array().isNaN().all() ||
                               (r * r.transpose() - Eigen::Matrix3d::Identity())
                                       .cwiseAbs()
                                       .maxCoeff() <= 1e-6;
      if (shapes.points_in_camera[t].cols() != shapes.NumPoints() ||
          shapes.points_in_object[t].cols() != shapes.NumPoints() ||
          !PointsFiniteOrLeftOut(shapes.points_in_object[t]) || !rotation_ok)
        std::abort();
    }
  }
  return 0;
}
