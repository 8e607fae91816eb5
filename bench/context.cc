#include "bench/context.h"

#include <ceres/version.h>
#include <unistd.h>

#include <Eigen/Core>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <string>
#include <thread>

namespace nrsfm {
namespace bench {
namespace {

std::string ReadLink(const std::string& path) {
  std::error_code error;
  const auto target = std::filesystem::canonical(path, error);
  return error ? std::string("unknown") : target.string();
}

std::string CommandOutput(const std::string& command) {
  std::string output;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return output;
  char buffer[256];
  while (fgets(buffer, sizeof(buffer), pipe) != nullptr) output += buffer;
  pclose(pipe);
  while (!output.empty() && (output.back() == '\n' || output.back() == ' ')) {
    output.pop_back();
  }
  return output;
}

}  // namespace

Json ContextBlock(int threads) {
  Json context;
  const std::time_t now = std::time(nullptr);
  char date[64];
  std::strftime(date, sizeof(date), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  context["date"] = date;
  char host[256] = {0};
  gethostname(host, sizeof(host) - 1);
  context["hostname"] = host;
  context["nproc"] = std::thread::hardware_concurrency();
  context["threads"] = threads;
  std::string cpu = CommandOutput(
      "grep -m1 'model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2");
  if (!cpu.empty() && cpu[0] == ' ') cpu.erase(0, 1);
  context["cpu"] = cpu;
#if defined(__clang__)
  context["compiler"] = std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
  context["compiler"] = std::string("g++ ") + __VERSION__;
#else
  context["compiler"] = "unknown";
#endif
#ifdef NDEBUG
  context["build"] = "Release (NDEBUG)";
#else
  context["build"] = "assertions on (not Release)";
#endif
  context["ceres"] = CERES_VERSION_STRING;
  context["eigen"] = std::to_string(EIGEN_WORLD_VERSION) + "." +
                     std::to_string(EIGEN_MAJOR_VERSION) + "." +
                     std::to_string(EIGEN_MINOR_VERSION);
  context["blas"] = ReadLink("/etc/alternatives/libblas.so.3-x86_64-linux-gnu");
  context["lapack"] =
      ReadLink("/etc/alternatives/liblapack.so.3-x86_64-linux-gnu");
  context["ceres_sparse"] = CommandOutput(
      "grep -E '^#define "
      "CERES_(USE_EIGEN_SPARSE|NO_SUITESPARSE|USE_CXX_THREADS|"
      "USE_OPENMP)' /usr/include/ceres/internal/config.h 2>/dev/null | "
      "awk '{print $2}' | tr '\\n' ' '");
  return context;
}

}  // namespace bench
}  // namespace nrsfm
