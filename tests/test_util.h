// Helpers shared by the tests.
#ifndef NRSFM_TESTS_TEST_UTIL_H_
#define NRSFM_TESTS_TEST_UTIL_H_

#include <string>

namespace nrsfm {
namespace testing_util {

// True in the NRSFM_SANITIZE build (ASan + UBSan, -O1; GCC and clang define
// __SANITIZE_ADDRESS__ under -fsanitize=address), where the slowest tests run
// the same checks on smaller problems to stay inside CI's time.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitizedBuild = true;
#else
inline constexpr bool kSanitizedBuild = false;
#endif

// Directory of the real datasets (`../shared/datasets`), or "" when absent.
// NRSFM_SHARED_DIR in the environment overrides the default location.
std::string SharedDatasetsDir();

// A fresh, empty directory under the test's temporary directory (TMPDIR;
// ctest sets it to the build's tests/ folder).
std::string MakeTempDir(const std::string& prefix);

// Removes every directory MakeTempDir made in this process (the test main
// does when all tests passed; a failed run keeps them to look at).
void RemoveTempDirs();

// The whole content of a file ("" when it cannot be read).
std::string ReadFileToString(const std::string& path);

// Exit code (-1 when killed by a signal) and output of a shell command.
struct CommandResult {
  int exit_code = -1;
  std::string out, err;
};

// Runs `executable args` with `dir` as the working directory, capturing
// stdout and stderr through files in `dir`.
CommandResult RunInDirectory(const std::string& dir,
                             const std::string& executable,
                             const std::string& args);

// True when the environment sets NRSFM_REQUIRE_SHARED=1 (.ci/run does): a
// test that needs the shared datasets then fails without them instead of
// skipping, so that CI cannot pass with the real-data tests unrun.
bool SharedDataRequired();

}  // namespace testing_util
}  // namespace nrsfm

// Skips the current test when the shared datasets are not there (fails it
// when NRSFM_REQUIRE_SHARED=1).
#define NRSFM_SKIP_WITHOUT_SHARED_DATA(dir_var)                           \
  const std::string dir_var = ::nrsfm::testing_util::SharedDatasetsDir(); \
  if (dir_var.empty()) {                                                  \
    if (::nrsfm::testing_util::SharedDataRequired()) {                    \
      FAIL() << "../shared/datasets not present (NRSFM_SHARED_DIR: the "  \
                "folder that holds "                                      \
                "datasets/), and NRSFM_REQUIRE_SHARED=1 requires them";   \
    }                                                                     \
    GTEST_SKIP() << "../shared/datasets not present";                     \
  }                                                                       \
  static_assert(true, "")

#endif  // NRSFM_TESTS_TEST_UTIL_H_
