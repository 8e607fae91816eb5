// The commands of the nrsfm tool. main() parses the flags into CommandFlags
// (tools/command_flags.h); each command returns a Status whose message is
// the one line the user sees. The steps they share with the Python module
// are in tools/reconstruction_steps.h and tools/synth_steps.h.
#ifndef NRSFM_TOOLS_COMMANDS_H_
#define NRSFM_TOOLS_COMMANDS_H_

#include <ostream>
#include <string>

#include "core/model/status.h"
#include "tools/command_flags.h"
#include "tools/reconstruction_steps.h"  // VersionString()

namespace nrsfm {
namespace tools {

Status RunReconstruct(const CommandFlags& flags, std::ostream& out,
                      std::ostream& progress);
Status RunEvaluate(const CommandFlags& flags, std::ostream& out);
Status RunSynth(const CommandFlags& flags, std::ostream& out);

}  // namespace tools
}  // namespace nrsfm

#endif  // NRSFM_TOOLS_COMMANDS_H_
