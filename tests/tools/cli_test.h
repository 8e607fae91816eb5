// The fixture of the tests that drive the real `nrsfm` binary through its
// commands (tests/tools/cli_test.cc: synth -> reconstruct -> evaluate round
// trips, bad input, --help and --flagfile; cli_real_data_test.cc: the real
// sequences with default options): ToolTest with the evaluate JSON of a
// result and the check of a bad input's failure.
#ifndef NRSFM_TESTS_TOOLS_CLI_TEST_H_
#define NRSFM_TESTS_TOOLS_CLI_TEST_H_

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/test_util.h"
#include "tests/tools/tool_test.h"

namespace nrsfm {

class CliTest : public ToolTest {
 protected:
  using RunResult = testing_util::CommandResult;

  CliTest() : ToolTest("nrsfm_cli") {}

  static std::string ReadFile(const std::filesystem::path& path) {
    return testing_util::ReadFileToString(path.string());
  }

  // The evaluate JSON line of a result directory against a truth file.
  nlohmann::json Evaluate(const std::string& truth, const std::string& result) {
    const RunResult r =
        Run("evaluate --truth " + truth + " --result " + result);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(r.out);
  }

  // Expects the failure of a bad input (docs/reliability.md, "Bad input and
  // failure behaviour"): exit code `exit_code` (1; 2 for a command line that
  // names no command), exactly one line on stderr that contains `needle` (the
  // message's own text), no crash report, and no output `out` left behind.
  void ExpectFailure(const std::string& args, const std::string& needle,
                     const std::string& out = "", int exit_code = 1) {
    const RunResult r = Run(args);
    EXPECT_EQ(r.exit_code, exit_code) << args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n"
                                                               << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos)
        << "args: " << args << "\nstderr: " << r.err;
    for (const char* crash :
         {"terminate", "Sanitizer", "Check failed", "runtime error"}) {
      EXPECT_EQ(r.err.find(crash), std::string::npos) << args << "\n" << r.err;
    }
    if (!out.empty()) {
      EXPECT_FALSE(std::filesystem::exists(Path(out))) << args;
    }
  }
};

}  // namespace nrsfm

#endif  // NRSFM_TESTS_TOOLS_CLI_TEST_H_
