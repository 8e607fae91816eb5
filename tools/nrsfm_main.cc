// nrsfm: reconstruct, evaluate and synthesise non-rigid structure from motion.
//
//   nrsfm reconstruct --input PATH --K N|auto --output DIR [options]
//   nrsfm evaluate --truth PATH --result DIR
//   nrsfm synth --dataset random|superquadric|shoe --output PATH.mat [options]
//   nrsfm synth --dataset reproject --input TRUTH.mat --output PATH.mat
//   [options] nrsfm view --result DIR [--truth PATH] [--input PATH] --output
//   FILE.html
//   nrsfm track --frames_dir DIR | --video FILE [--queries Q.csv] [--mask DIR]
//   --output DIR
//
// Flags may also come from a file: --flagfile=PATH. Logs go to stderr. The
// exit code is 0 only on success.
#include <gflags/gflags.h>
#include <glog/logging.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "tools/command_flags.h"
#include "tools/commands.h"
#include "tools/view_command.h"

namespace {

constexpr char kUsage[] =
    "non-rigid structure from motion.\n\n"
    "Usage:\n"
    "  nrsfm reconstruct --input PATH --K N|auto --output DIR [options]\n"
    "  nrsfm evaluate --truth PATH --result DIR\n"
    "  nrsfm synth --dataset random|superquadric|shoe --output PATH.mat "
    "[options]\n"
    "  nrsfm synth --dataset reproject --input TRUTH.mat --output PATH.mat "
    "[options]\n"
    "  nrsfm view --result DIR [--truth PATH] [--input PATH] --output "
    "FILE.html\n"
    "  nrsfm track --frames_dir DIR | --video FILE [--queries Q.csv] [--mask "
    "DIR] "
    "--output DIR\n"
    "\n"
    "reconstruct reads W (2F x P, rows u_t, v_t interleaved; 2FM x P for M\n"
    "cameras), NaN = missing, or detector keypoints (COCO results .json, a\n"
    "folder of OpenPose .json frames; pixels, v down; docs/inputs.md), and\n"
    "writes points_camera.csv, points_object.csv,\n"
    "rotations.csv, weights.csv, basis.csv and result.json into DIR.\n"
    "evaluate prints one JSON line with e3d, frob_zsign, error3d_pct, "
    "zerror_pct,\n"
    "F and P. synth writes a .mat with W and the ground truth P3_gt "
    "(reproject:\n"
    "the truth of --input seen by another camera path, with S and Rs).\n"
    "view writes one self-contained HTML page (works offline): the 3D points\n"
    "animated over the frames, the truth (--truth, --truth_var) aligned as "
    "for\n"
    "e3D with the per-frame error, and the 2D tracks (--input, --var, "
    "--mask_var,\n"
    "--format) with their reprojections; --overwrite replaces an existing "
    "page.\n"
    "track follows points through frames (docs/tracking.md) and writes\n"
    "tracks.csv, tracks.mat (reconstruct --input DIR reads it) and "
    "result.json.\n"
    "Flags may be read from a file with --flagfile=PATH. Exit code 0 = "
    "success.";

bool WantsHelp(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-help" || arg == "-h" || arg == "help" ||
        arg == "--helpfull") {
      return true;
    }
  }
  return false;
}

// glibc's malloc with transparent huge pages (the glibc.malloc.hugetlb
// tunable, glibc ≥ 2.35; read only at start-up, hence the re-execution): a
// large reconstruction allocates gigabytes in many small blocks, and on a
// virtual machine every first touch of a 4 KiB page is a costly fault. F 300
// × P 10 000 × K 5: 64 → 32 s, 2.3 M → 50 k page faults
// (docs/performance.md). The tool re-executes itself once with the tunable
// set unless GLIBC_TUNABLES is already set (the caller's choice, or this
// re-execution); when execv fails it runs on as it is.
void ReexecWithHugePages(char** argv) {
  if (std::getenv("GLIBC_TUNABLES") != nullptr) return;
  if (setenv("GLIBC_TUNABLES", "glibc.malloc.hugetlb=1", 1) != 0) return;
  execv("/proc/self/exe", argv);
  unsetenv("GLIBC_TUNABLES");  // execv failed: on without it
}

// `nrsfm track` is the program nrsfm-track beside this one (tools/
// track_main.cc): the tracker links OpenCV, which this program does not
// load. Returns only when it cannot be started.
nrsfm::Status RunTracker(const std::vector<char*>& argv) {
  std::error_code ec;
  const std::filesystem::path self =
      std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::string tracker =
      (ec ? std::filesystem::path(argv[0]).parent_path() : self.parent_path()) /
      "nrsfm-track";
  execv(tracker.c_str(), argv.data());
  return nrsfm::Status::Error("cannot run " + tracker + " (" +
                              std::strerror(errno) +
                              "); it is built and installed with nrsfm");
}

}  // namespace

int main(int argc, char** argv) {
  ReexecWithHugePages(argv);
  // The command line as given, for `track` (gflags removes the flags).
  std::vector<char*> original_argv(argv, argv + argc);
  original_argv.push_back(nullptr);
  // The flags parse into `flags` (tools/command_flags.h).
  static nrsfm::tools::CommandFlags flags;
  nrsfm::tools::RegisterCommandFlags(&flags);
  FLAGS_logtostderr = true;
  gflags::SetUsageMessage(kUsage);
  gflags::SetVersionString(nrsfm::tools::VersionString());
  if (WantsHelp(argc, argv)) {
    // Only this tool's flags, not those of glog and gflags themselves.
    gflags::ShowUsageWithFlagsRestrict(argv[0],
                                       nrsfm::tools::kCommandFlagsFile);
    return 0;
  }
  gflags::ParseCommandLineFlags(&argc, &argv, /*remove_flags=*/true);
  google::InitGoogleLogging(argv[0]);

  if (argc != 2) {
    std::cerr << "nrsfm: expected exactly one command (reconstruct, evaluate, "
                 "synth, view or track), got "
              << argc - 1 << "; see nrsfm --help\n";
    return 2;
  }
  const std::string command = argv[1];
  nrsfm::Status status;
  if (command == "reconstruct") {
    status = nrsfm::tools::RunReconstruct(flags, std::cout, std::cerr);
  } else if (command == "evaluate") {
    status = nrsfm::tools::RunEvaluate(flags, std::cout);
  } else if (command == "synth") {
    status = nrsfm::tools::RunSynth(flags, std::cout);
  } else if (command == "view") {
    status = nrsfm::tools::RunView(flags, std::cout);
  } else if (command == "track") {
    status = RunTracker(original_argv);
  } else {
    std::cerr
        << "nrsfm: unknown command '" << command
        << "' (expected reconstruct, evaluate, synth, view or track); see "
           "nrsfm "
           "--help\n";
    return 2;
  }
  if (!status.ok()) {
    std::cerr << "nrsfm " << command << ": error: " << status.message() << "\n";
    return 1;
  }
  return 0;
}
