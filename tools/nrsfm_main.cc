// nrsfm: reconstruct, evaluate and synthesise non-rigid structure from motion.
//
//   nrsfm reconstruct --input PATH --K N|auto --output DIR [options]
//   nrsfm evaluate --truth PATH --result DIR
//   nrsfm synth --dataset random|superquadric|shoe --output PATH.mat [options]
//   nrsfm synth --dataset reproject --input TRUTH.mat --output PATH.mat
//   [options] nrsfm view --result DIR [--truth PATH] [--input PATH] --output
//   FILE.html
//
// Flags may also come from a file: --flagfile=PATH. Logs go to stderr. The
// exit code is 0 only on success.
#include <gflags/gflags.h>
#include <glog/logging.h>
#include <unistd.h>

#include <cstdlib>
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

}  // namespace

int main(int argc, char** argv) {
  ReexecWithHugePages(argv);
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
                 "synth or view), got "
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
  } else {
    std::cerr << "nrsfm: unknown command '" << command
              << "' (expected reconstruct, evaluate, synth or view); see nrsfm "
                 "--help\n";
    return 2;
  }
  if (!status.ok()) {
    std::cerr << "nrsfm " << command << ": error: " << status.message() << "\n";
    return 1;
  }
  return 0;
}
