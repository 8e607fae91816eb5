// nrsfm track: point tracks from a folder of frames or a video
// (track/tracker.h; docs/tracking.md). Writes into --output tracks.csv,
// tracks.mat (what `nrsfm reconstruct --input OUT` reads) and result.json;
// every input is checked, and the frames tracked, before anything is
// written. Progress lines go to `progress` unless --quiet.
#ifndef NRSFM_TOOLS_TRACK_COMMAND_H_
#define NRSFM_TOOLS_TRACK_COMMAND_H_

#include <ostream>

#include "core/model/status.h"
#include "tools/command_flags.h"

namespace nrsfm {
namespace tools {

Status RunTrack(const CommandFlags& flags, std::ostream& out,
                std::ostream& progress);

}  // namespace tools
}  // namespace nrsfm

#endif  // NRSFM_TOOLS_TRACK_COMMAND_H_
