// nrsfm_bench: placeholder until the benchmark suites land. It only checks that
// the library links and runs.
#include <iostream>

#include <gflags/gflags.h>
#include <glog/logging.h>

#include "core/model.h"

int main(int argc, char** argv) {
  FLAGS_logtostderr = true;
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  google::InitGoogleLogging(argv[0]);
  nrsfm::Model model;
  model.Resize(1, 1, 1, 1);
  std::cout << "nrsfm_bench: benchmark suites not implemented yet (stub run)\n";
  return 0;
}
