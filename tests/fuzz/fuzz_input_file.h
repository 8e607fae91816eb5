// Helper for the fuzz targets: the readers take a path, so each input is
// written to one temporary file per process (its name ends in the extension
// the reader dispatches on), or split into the files of one temporary
// directory (a result directory).
#ifndef NRSFM_TESTS_FUZZ_FUZZ_INPUT_FILE_H_
#define NRSFM_TESTS_FUZZ_FUZZ_INPUT_FILE_H_

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace nrsfm {
namespace fuzz {

// "$TMPDIR/nrsfm_fuzz_<pid><suffix>": one path per process and use.
inline std::string TempPath(const std::string& suffix) {
  const char* tmp = std::getenv("TMPDIR");
  return std::string(tmp != nullptr ? tmp : "/tmp") + "/nrsfm_fuzz_" +
         std::to_string(getpid()) + suffix;
}

inline void WriteBytes(const std::string& path, const std::uint8_t* data,
                       std::size_t size) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, file) != size) std::abort();
  if (std::fclose(file) != 0) std::abort();
}

// Writes data[0..size) to "$TMPDIR/nrsfm_fuzz_<pid><extension>" (replacing
// it) and returns the path. These functions abort if a file cannot be
// written: that is a broken fuzzing set-up, not a finding.
inline std::string WriteInputFile(const std::uint8_t* data, std::size_t size,
                                  const std::string& extension) {
  const std::string path = TempPath(extension);
  WriteBytes(path, data, size);
  return path;
}

// The byte that separates the files of an input that is a whole directory
// (a form feed: rare in text, so a mutation seldom adds one).
constexpr std::uint8_t kFileSeparator = '\f';

// Writes the input as the files `names` of the directory
// "$TMPDIR/nrsfm_fuzz_<pid>_dir" (made if needed) and returns the directory:
// the bytes up to the first kFileSeparator are the first file, those up to
// the next the second, and so on; files beyond the last separator are empty.
inline std::string WriteInputDirectory(const std::uint8_t* data,
                                       std::size_t size,
                                       const std::vector<std::string>& names) {
  const std::string dir = TempPath("_dir");
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) std::abort();
  std::size_t begin = 0;
  for (const std::string& name : names) {
    std::size_t end = begin;
    while (end < size && data[end] != kFileSeparator) ++end;
    WriteBytes(dir + "/" + name, data + begin, end - begin);
    begin = end < size ? end + 1 : size;
  }
  return dir;
}

}  // namespace fuzz
}  // namespace nrsfm

#endif  // NRSFM_TESTS_FUZZ_FUZZ_INPUT_FILE_H_
