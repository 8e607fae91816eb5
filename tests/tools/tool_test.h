// The fixture of the tests that drive the real `nrsfm` binary (NRSFM_CLI,
// defined by each such test target): a fresh temporary directory per test,
// where the tool runs, removed afterwards.
#ifndef NRSFM_TESTS_TOOLS_TOOL_TEST_H_
#define NRSFM_TESTS_TOOLS_TOOL_TEST_H_

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>

#include "tests/test_util.h"

namespace nrsfm {

class ToolTest : public ::testing::Test {
 protected:
  // `prefix` names the temporary directories (testing_util::MakeTempDir).
  explicit ToolTest(std::string prefix) : prefix_(std::move(prefix)) {}

  void SetUp() override {
    dir_ = testing_util::MakeTempDir(prefix_);
    ASSERT_FALSE(dir_.empty());
  }
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }

  // Runs `nrsfm <args>` in the test directory.
  testing_util::CommandResult Run(const std::string& args) {
    return testing_util::RunInDirectory(dir_, NRSFM_CLI, args);
  }

  // `name` in the test directory.
  std::string Path(const std::string& name) const {
    return (std::filesystem::path(dir_) / name).string();
  }

  std::string dir_;

 private:
  const std::string prefix_;
};

}  // namespace nrsfm

#endif  // NRSFM_TESTS_TOOLS_TOOL_TEST_H_
