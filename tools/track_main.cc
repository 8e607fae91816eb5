// nrsfm-track: the `track` command of nrsfm (tools/track_command.h), which
// `nrsfm track …` runs; its own program because it links OpenCV. Same flags,
// same messages, same exit codes as nrsfm.
#include <gflags/gflags.h>
#include <glog/logging.h>

#include <iostream>
#include <string>

#include "tools/command_flags.h"
#include "tools/reconstruction_steps.h"  // VersionString()
#include "tools/track_command.h"
#include "track/frame_source.h"

int main(int argc, char** argv) {
  static nrsfm::tools::CommandFlags flags;
  nrsfm::tools::RegisterCommandFlags(&flags);
  FLAGS_logtostderr = true;
  gflags::SetUsageMessage(
      "nrsfm track --frames_dir DIR | --video FILE "
      "[--queries Q.csv] [--mask DIR] --output DIR");
  gflags::SetVersionString(nrsfm::tools::VersionString());
  gflags::ParseCommandLineFlags(&argc, &argv, /*remove_flags=*/true);
  google::InitGoogleLogging(argv[0]);
  nrsfm::track::QuietOpenCvLog();
  if (argc != 2 || std::string(argv[1]) != "track") {
    std::cerr << "nrsfm-track: expected the command track (run as nrsfm "
                 "track); see nrsfm --help\n";
    return 2;
  }
  const nrsfm::Status status =
      nrsfm::tools::RunTrack(flags, std::cout, std::cerr);
  if (!status.ok()) {
    std::cerr << "nrsfm track: error: " << status.message() << "\n";
    return 1;
  }
  return 0;
}
