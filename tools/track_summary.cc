#include "tools/track_summary.h"

#include "tools/flag_table.h"
#include "tools/reconstruction_steps.h"

namespace nrsfm {
namespace tools {

nlohmann::json TrackSummaryJson(const CommandFlags& flags,
                                const std::string& source, int width,
                                int height, const track::Tracks& tracks) {
  nlohmann::json result;
  result["version"] = VersionString();
  result["source"] = source;
  result["frames"] = tracks.x.rows();
  result["points"] = tracks.x.cols();
  result["width"] = width;
  result["height"] = height;
  nlohmann::json options = nlohmann::json::object();
  for (const FlagInfo& flag : CommandFlagTable()) {
    if (flag.role == FlagRole::kTracking) options[flag.name] = flag.text(flags);
  }
  result["options"] = options;
  result["window_start_frames"] = nlohmann::json::array();
  for (int w : tracks.window_start) {
    result["window_start_frames"].push_back(tracks.frame_numbers[w]);
  }
  result["window_rank"] = tracks.window_rank;
  result["windows_without_basis"] = tracks.windows_without_basis;
  result["points_lost"] = track::PointsLost(tracks);
  result["visible_fraction"] =
      tracks.visible.size() == 0
          ? 0.0
          : static_cast<double>(tracks.visible.sum()) / tracks.visible.size();
  result["seconds"] = tracks.seconds;
  return result;
}

}  // namespace tools
}  // namespace nrsfm
