// nrsfm: reconstruct, evaluate and synthesise non-rigid structure from motion.
//
//   nrsfm reconstruct --input PATH --K N|auto --output DIR [options]
//   nrsfm evaluate --truth PATH --result DIR
//   nrsfm synth --dataset random|superquadric|shoe --output PATH.mat [options]
//   nrsfm view --result DIR [--truth PATH] [--input PATH] --output FILE.html
//
// Flags may also come from a file: --flagfile=PATH. Logs go to stderr. The
// exit code is 0 only on success.
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include <gflags/gflags.h>
#include <glog/logging.h>

#include "tools/commands.h"
#include "tools/view_command.h"

DEFINE_string(input, "", "reconstruct: input file (.mat v4/v5/v7.3, text/CSV W, or an "
              "observation list .obs/.list 'frame camera point u v').");
DEFINE_string(var, "", "reconstruct: variable of a .mat input (default: W, then P3_gt, "
              "then X).");
DEFINE_string(mask_var, "", "reconstruct: optional visibility-mask variable of a .mat "
              "input (nonzero = visible).");
DEFINE_string(format, "auto", "reconstruct: input format auto|mat|text|list.");
DEFINE_string(K, "", "reconstruct: number of basis shapes, an integer >= 1 or 'auto'; "
              "synth: basis shapes of the random generator (default 5).");
DEFINE_int32(K_max, 8, "reconstruct --K auto: largest K tried.");
DEFINE_double(K_threshold, 1.1, "reconstruct --K auto: keep the smallest K whose "
              "reprojection RMS is within this factor of the noise level estimated "
              "from the data.");
DEFINE_string(output, "", "reconstruct: output directory; synth: output .mat file.");
DEFINE_bool(overwrite, false, "reconstruct: replace a non-empty output directory.");
DEFINE_bool(ply, false, "reconstruct: also write one PLY file per frame.");
DEFINE_string(init, "auto", "reconstruct: start auto|factorization|rigid|triple.");
DEFINE_double(smoothness, 0.0, "reconstruct: weight of the Delaunay-neighbour "
              "smoothness term (0 = off).");
DEFINE_double(temporal, 0.0, "reconstruct: weight of the temporal smoothness of the "
              "deformation weights, l_t - l_(t-1) (0 = off; see docs/extra_terms.md).");
DEFINE_double(temporal_rotations, 0.0, "reconstruct: weight of the temporal smoothness "
              "of the rotations between consecutive frames (0 = off). Keep it far below "
              "--temporal (about 1/300): it trades real rotation for deformation.");
DEFINE_double(temporal_shape, 0.0, "reconstruct: weight of the temporal smoothness "
              "of the 3D shape in the object frame, S_t - S_(t-1) per point (0 = off; "
              "dimensionless; see docs/extra_terms.md).");
DEFINE_double(rotation_acceleration, 0.0, "reconstruct: weight of the temporal "
              "smoothness of the angular velocity, log(R_(t+1) R_t^T) - log(R_t R_(t-1)^T) "
              "(0 = off; dimensionless; see docs/extra_terms.md).");
DEFINE_double(rigidity, 0.0, "reconstruct: weight of the multi-camera rigidity term "
              "(0 = off; needs --cameras >= 2).");
DEFINE_int32(cameras, 1, "reconstruct: number of synchronised cameras M of a W "
             "input with 2FM rows.");
DEFINE_string(robust, "none", "reconstruct: robust loss none|huber|cauchy on the "
              "reprojection terms.");
DEFINE_double(robust_scale, 1.0, "reconstruct: robust loss scale, in input units.");
DEFINE_int32(max_iterations, 100, "reconstruct: Levenberg-Marquardt iterations.");
DEFINE_int32(threads, 1, "reconstruct: solver threads.");
DEFINE_string(linear_solver, "auto", "reconstruct: auto|dense_schur|sparse_schur|"
              "iterative_schur|sparse_normal_cholesky|cgnr|dense_qr.");
DEFINE_uint64(seed, 1, "reconstruct: seed of the rigid start; synth: seed.");
DEFINE_string(truth, "", "reconstruct/evaluate: ground truth (.mat with S+Rs, P3_gt "
              "or X, or a result directory).");
DEFINE_string(truth_var, "", "reconstruct/evaluate: variable of the truth .mat "
              "(default: S+Rs, then P3_gt, then X).");
DEFINE_string(result, "", "evaluate: result directory of a reconstruction.");
DEFINE_string(dataset, "random", "synth: random|superquadric|shoe.");
DEFINE_int32(frames, -1, "synth: frames F (default: the generator's).");
DEFINE_int32(points, -1, "synth: points P (default: the generator's).");
DEFINE_double(noise, 0.0, "synth: Gaussian noise std on W, input units.");
DEFINE_double(missing, 0.0, "synth: fraction of entries removed at random "
              "(random, superquadric).");
DEFINE_bool(quiet, false, "reconstruct: no progress lines on stderr.");

namespace {

constexpr char kUsage[] =
    "non-rigid structure from motion.\n\n"
    "Usage:\n"
    "  nrsfm reconstruct --input PATH --K N|auto --output DIR [options]\n"
    "  nrsfm evaluate --truth PATH --result DIR\n"
    "  nrsfm synth --dataset random|superquadric|shoe --output PATH.mat [options]\n"
    "  nrsfm view --result DIR [--truth PATH] [--input PATH] --output FILE.html\n"
    "\n"
    "reconstruct reads W (2F x P, rows u_t, v_t interleaved; 2FM x P for M\n"
    "cameras), NaN = missing, and writes points_camera.csv, points_object.csv,\n"
    "rotations.csv, weights.csv, basis.csv and result.json into DIR.\n"
    "evaluate prints one JSON line with e3d, frob_zsign, error3d_pct, zerror_pct,\n"
    "F and P. synth writes a .mat with W and the ground truth P3_gt.\n"
    "view writes one self-contained HTML page (works offline): the 3D points\n"
    "animated over the frames, the truth (--truth, --truth_var) aligned as for\n"
    "e3D with the per-frame error, and the 2D tracks (--input, --var, --mask_var,\n"
    "--format) with their reprojections; --overwrite replaces an existing page.\n"
    "Flags may be read from a file with --flagfile=PATH. Exit code 0 = success.";

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

}  // namespace

int main(int argc, char** argv) {
  FLAGS_logtostderr = true;
  gflags::SetUsageMessage(kUsage);
  gflags::SetVersionString(nrsfm::tools::VersionString());
  if (WantsHelp(argc, argv)) {
    // Only this tool's flags, not those of glog and gflags themselves.
    gflags::ShowUsageWithFlagsRestrict(argv[0], "nrsfm_main");
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
  nrsfm::tools::CommandFlags flags;
  flags.input = FLAGS_input;
  flags.var = FLAGS_var;
  flags.mask_var = FLAGS_mask_var;
  flags.format = FLAGS_format;
  flags.K = FLAGS_K;
  flags.K_max = FLAGS_K_max;
  flags.K_threshold = FLAGS_K_threshold;
  flags.output = FLAGS_output;
  flags.overwrite = FLAGS_overwrite;
  flags.ply = FLAGS_ply;
  flags.init = FLAGS_init;
  flags.smoothness = FLAGS_smoothness;
  flags.temporal = FLAGS_temporal;
  flags.temporal_rotations = FLAGS_temporal_rotations;
  flags.temporal_shape = FLAGS_temporal_shape;
  flags.rotation_acceleration = FLAGS_rotation_acceleration;
  flags.rigidity = FLAGS_rigidity;
  flags.cameras = FLAGS_cameras;
  flags.robust = FLAGS_robust;
  flags.robust_scale = FLAGS_robust_scale;
  flags.max_iterations = FLAGS_max_iterations;
  flags.threads = FLAGS_threads;
  flags.linear_solver = FLAGS_linear_solver;
  flags.seed = FLAGS_seed;
  flags.truth = FLAGS_truth;
  flags.truth_var = FLAGS_truth_var;
  flags.result = FLAGS_result;
  flags.dataset = FLAGS_dataset;
  flags.frames = FLAGS_frames;
  flags.points = FLAGS_points;
  flags.noise = FLAGS_noise;
  flags.missing = FLAGS_missing;
  flags.quiet = FLAGS_quiet;

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
              << "' (expected reconstruct, evaluate, synth or view); see nrsfm --help\n";
    return 2;
  }
  if (!status.ok()) {
    std::cerr << "nrsfm " << command << ": error: " << status.message() << "\n";
    return 1;
  }
  return 0;
}
