// Test main: glog goes to stderr (never log files in /tmp); the temporary
// directories of a run whose tests all passed are removed.
#include <gflags/gflags.h>
#include <glog/logging.h>
#include <gtest/gtest.h>

#include "tests/test_util.h"

int main(int argc, char** argv) {
  FLAGS_logtostderr = true;
  testing::InitGoogleTest(&argc, argv);
  google::InitGoogleLogging(argv[0]);
  const int result = RUN_ALL_TESTS();
  if (result == 0) nrsfm::testing_util::RemoveTempDirs();
  return result;
}
