#include "bench/measure.h"

#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

namespace nrsfm {
namespace bench {
namespace {

double StatusFieldMb(const char* field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  const std::string key = std::string(field) + ":";
  while (std::getline(status, line)) {
    if (line.rfind(key, 0) == 0) {
      return std::atof(line.c_str() + key.size()) / 1024.0;  // kB -> MB
    }
  }
  return std::nan("");
}

}  // namespace

ChildResult RunInChild(const std::function<Json()>& work) {
  ChildResult result;
  int fds[2];
  if (pipe(fds) != 0) {
    result.message = "pipe() failed";
    return result;
  }
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    result.message = "fork() failed";
    return result;
  }
  if (pid == 0) {
    close(fds[0]);
    Json out;
    out["start_rss_mb"] = StatusFieldMb("VmRSS");
    out["payload"] = work();
    out["peak_rss_mb"] = StatusFieldMb("VmHWM");
    const std::string text = out.dump();
    size_t written = 0;
    while (written < text.size()) {
      const ssize_t n =
          write(fds[1], text.data() + written, text.size() - written);
      if (n <= 0) break;
      written += static_cast<size_t>(n);
    }
    close(fds[1]);
    _exit(0);
  }
  close(fds[1]);
  std::string text;
  char buffer[4096];
  ssize_t n;
  while ((n = read(fds[0], buffer, sizeof(buffer))) > 0) {
    text.append(buffer, static_cast<size_t>(n));
  }
  close(fds[0]);
  int wstatus = 0;
  waitpid(pid, &wstatus, 0);
  if (!WIFEXITED(wstatus) || WEXITSTATUS(wstatus) != 0 || text.empty()) {
    result.message = "child failed";
    return result;
  }
  const Json out = Json::parse(text, nullptr, false);
  if (out.is_discarded()) {
    result.message = "child sent bad JSON";
    return result;
  }
  result.ok = true;
  result.start_rss_mb = out.value("start_rss_mb", 0.0);
  result.peak_rss_mb = out.value("peak_rss_mb", 0.0);
  result.payload = out["payload"];
  return result;
}

double NowSeconds() {
  return std::chrono::duration<double>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace bench
}  // namespace nrsfm
