// The summary of one tracking run (track/tracker.h): what `nrsfm track`
// writes as result.json and the MATLAB function nrsfm_track returns as its
// info struct (docs/tracking.md).
#ifndef NRSFM_TOOLS_TRACK_SUMMARY_H_
#define NRSFM_TOOLS_TRACK_SUMMARY_H_

#include <nlohmann/json.hpp>
#include <string>

#include "tools/command_flags.h"
#include "track/tracks.h"

namespace nrsfm {
namespace tools {

// version, source (the frames' name), frames, points, width, height
// (pixels), options (every tracking flag as text), window_start_frames
// (frame numbers), window_rank, windows_without_basis, points_lost,
// visible_fraction and seconds.
nlohmann::json TrackSummaryJson(const CommandFlags& flags,
                                const std::string& source, int width,
                                int height, const track::Tracks& tracks);

}  // namespace tools
}  // namespace nrsfm

#endif  // NRSFM_TOOLS_TRACK_SUMMARY_H_
