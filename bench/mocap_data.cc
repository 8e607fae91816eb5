#include "bench/mocap_data.h"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <utility>

#include "core/io/read_measurements.h"

namespace nrsfm {
namespace bench {

bool LoadMocapSequences(const BenchConfig& config,
                        std::vector<MocapSequence>* sequences,
                        std::string* why) {
  namespace fs = std::filesystem;
  sequences->clear();
  std::error_code error;
  if (config.datasets_dir.empty() ||
      !fs::is_directory(config.datasets_dir, error)) {
    *why = "no datasets directory '" + config.datasets_dir +
           "' (set --datasets_dir)";
    return false;
  }
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(config.datasets_dir, error)) {
    if (entry.path().extension() == ".mat")
      files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  for (const std::string& file : files) {
    MocapSequence sequence;
    sequence.name = fs::path(file).stem().string();
    if (!config.mocap_sequences.empty() &&
        ("," + config.mocap_sequences + ",").find("," + sequence.name + ",") ==
            std::string::npos) {
      continue;
    }
    Status status =
        ReadMeasurements(file, InputOptions(), &sequence.measurements);
    if (status.ok()) status = ReadGroundTruth(file, "", &sequence.truth);
    if (!status.ok()) {
      std::cout << "skip " << file << ": " << status.message() << "\n";
      continue;
    }
    sequences->push_back(std::move(sequence));
  }
  if (sequences->empty()) {
    *why = "no .mat with ground truth in " + config.datasets_dir;
    return false;
  }
  return true;
}

int PublishedNumBases(const std::string& name) {
  if (name == "drink" || name == "pickup") return 12;
  if (name == "yoga") return 10;
  if (name == "face") return 7;
  return 8;
}

}  // namespace bench
}  // namespace nrsfm
