#include "tests/test_util.h"

#include <cstdlib>
#include <filesystem>
#include <random>

namespace nrsfm {
namespace testing_util {

std::string SharedDatasetsDir() {
  const char* env = std::getenv("NRSFM_SHARED_DIR");
  const std::filesystem::path shared = env ? env : NRSFM_DEFAULT_SHARED_DIR;
  const std::filesystem::path datasets = shared / "datasets";
  std::error_code ec;
  if (std::filesystem::is_directory(datasets, ec)) return datasets.string();
  return "";
}

std::string MakeTempDir(const std::string& prefix) {
  std::random_device rd;
  const std::filesystem::path base = std::filesystem::temp_directory_path();
  for (int attempt = 0; attempt < 100; ++attempt) {
    const std::filesystem::path dir =
        base / (prefix + "_" + std::to_string(rd()));
    std::error_code ec;
    if (std::filesystem::create_directory(dir, ec)) return dir.string();
  }
  return "";
}

}  // namespace testing_util
}  // namespace nrsfm
