// The commands of the nrsfm tool. main() parses the flags into CommandFlags;
// each command returns a Status whose message is the one line the user sees.
#ifndef NRSFM_TOOLS_COMMANDS_H_
#define NRSFM_TOOLS_COMMANDS_H_

#include <cstdint>
#include <ostream>
#include <string>

#include "core/status.h"

namespace nrsfm {
namespace tools {

// Mirrors the gflags of nrsfm_main.cc (see --help for their meaning).
struct CommandFlags {
  std::string input, var, mask_var, format = "auto";
  std::string K;
  int K_max = 8;
  double K_threshold = 1.1;
  std::string output;
  bool overwrite = false, ply = false;
  std::string init = "auto";
  double smoothness = 0.0, temporal = 0.0, temporal_rotations = 0.0, rigidity = 0.0;
  double temporal_shape = 0.0, rotation_acceleration = 0.0;
  int cameras = 1;
  std::string robust = "none";
  double robust_scale = 1.0;
  int max_iterations = 100;
  int threads = 1;
  std::string linear_solver = "auto";
  std::uint64_t seed = 1;
  std::string truth, truth_var, result;
  std::string dataset = "random";
  int frames = -1, points = -1;
  double noise = 0.0, missing = 0.0;
  bool quiet = false;
};

// "nrsfm <version> (Ceres <version>, Eigen <version>)".
const char* VersionString();

Status RunReconstruct(const CommandFlags& flags, std::ostream& out,
                      std::ostream& progress);
Status RunEvaluate(const CommandFlags& flags, std::ostream& out);
Status RunSynth(const CommandFlags& flags, std::ostream& out);

}  // namespace tools
}  // namespace nrsfm

#endif  // NRSFM_TOOLS_COMMANDS_H_
