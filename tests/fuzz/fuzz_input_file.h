// Helper for the fuzz targets: the readers take a path, so each input is
// written to one temporary file per process (its name ends in the extension
// the reader dispatches on).
#ifndef NRSFM_TESTS_FUZZ_FUZZ_INPUT_FILE_H_
#define NRSFM_TESTS_FUZZ_FUZZ_INPUT_FILE_H_

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace nrsfm {
namespace fuzz {

// Writes data[0..size) to "$TMPDIR/nrsfm_fuzz_<pid><extension>" (replacing
// it) and returns the path. Aborts if the file cannot be written: that is a
// broken fuzzing set-up, not a finding.
inline std::string WriteInputFile(const std::uint8_t* data, std::size_t size,
                                  const std::string& extension) {
  const char* tmp = std::getenv("TMPDIR");
  const std::string path = std::string(tmp != nullptr ? tmp : "/tmp") +
                           "/nrsfm_fuzz_" + std::to_string(getpid()) +
                           extension;
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, file) != size) std::abort();
  if (std::fclose(file) != 0) std::abort();
  return path;
}

}  // namespace fuzz
}  // namespace nrsfm

#endif  // NRSFM_TESTS_FUZZ_FUZZ_INPUT_FILE_H_
