#include "tests/test_util.h"

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <random>
#include <sstream>
#include <vector>

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

bool SharedDataRequired() {
  const char* env = std::getenv("NRSFM_REQUIRE_SHARED");
  return env != nullptr && std::string(env) == "1";
}

namespace {
std::mutex temp_dirs_mutex;
std::vector<std::string>& TempDirs() {
  static std::vector<std::string>* dirs = new std::vector<std::string>();
  return *dirs;
}
}  // namespace

std::string MakeTempDir(const std::string& prefix) {
  std::random_device rd;
  const std::filesystem::path base = std::filesystem::temp_directory_path();
  for (int attempt = 0; attempt < 100; ++attempt) {
    const std::filesystem::path dir =
        base / (prefix + "_" + std::to_string(rd()));
    std::error_code ec;
    if (std::filesystem::create_directory(dir, ec)) {
      std::lock_guard<std::mutex> lock(temp_dirs_mutex);
      TempDirs().push_back(dir.string());
      return dir.string();
    }
  }
  return "";
}

void RemoveTempDirs() {
  std::lock_guard<std::mutex> lock(temp_dirs_mutex);
  for (const std::string& dir : TempDirs()) {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
  TempDirs().clear();
}

std::string ReadFileToString(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

CommandResult RunInDirectory(const std::string& dir,
                             const std::string& executable,
                             const std::string& args) {
  const std::string out = (std::filesystem::path(dir) / "stdout.txt").string();
  const std::string err = (std::filesystem::path(dir) / "stderr.txt").string();
  const std::string command = "cd '" + dir + "' && '" + executable + "' " +
                              args + " >'" + out + "' 2>'" + err + "'";
  const int status = std::system(command.c_str());
  CommandResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.out = ReadFileToString(out);
  result.err = ReadFileToString(err);
  return result;
}

}  // namespace testing_util
}  // namespace nrsfm
