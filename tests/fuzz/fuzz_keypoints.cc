// libFuzzer target: the keypoint readers (core/io/keypoint_io.h) on arbitrary
// bytes: as one COCO results file, directly and through ReadMeasurements,
// and split at form feeds into the three files of an OpenPose folder.
// Whatever they accept must be valid measurements whose visible keypoints
// are finite with a score of at least min_confidence.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/io/keypoint_io.h"
#include "core/io/read_measurements.h"
#include "tests/fuzz/fuzz_input_file.h"

namespace {

void CheckKeypoints(const nrsfm::Keypoints& k, double min_confidence) {
  const nrsfm::Measurements& m = k.measurements;
  if (!m.Validate().ok() || m.num_cameras != 1 || m.NumVisible() < 1)
    std::abort();
  if (k.confidence.rows() != m.num_frames ||
      k.confidence.cols() != m.num_points)
    std::abort();
  for (int t = 0; t < m.num_frames; ++t) {
    for (int p = 0; p < m.num_points; ++p) {
      if (m.visible(t, p) &&
          !(k.confidence(t, p) >= min_confidence && k.confidence(t, p) > 0)) {
        std::abort();
      }
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data,
                                      std::size_t size) {
  const std::string path = nrsfm::fuzz::WriteInputFile(data, size, ".json");
  nrsfm::KeypointOptions options;
  options.min_confidence = 0.3;
  nrsfm::Keypoints keypoints;
  if (nrsfm::ReadCocoKeypoints(path, options, &keypoints).ok()) {
    CheckKeypoints(keypoints, options.min_confidence);
  }
  nrsfm::Measurements measurements;
  nrsfm::InputDetails details;
  if (nrsfm::ReadMeasurements(path, nrsfm::InputOptions(), &measurements,
                              &details)
          .ok()) {
    if (!measurements.Validate().ok() ||
        details.confidence.rows() != measurements.num_frames) {
      std::abort();
    }
  }
  const std::string dir = nrsfm::fuzz::WriteInputDirectory(
      data, size,
      {"f_1_keypoints.json", "f_2_keypoints.json", "f_10_keypoints.json"});
  if (nrsfm::ReadOpenPoseFolder(dir, options, &keypoints).ok()) {
    CheckKeypoints(keypoints, options.min_confidence);
  }
  return 0;
}
