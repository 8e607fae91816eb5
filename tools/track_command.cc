#include "tools/track_command.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "core/io/read_measurements.h"
#include "tools/flag_table.h"
#include "tools/track_summary.h"
#include "track/tracker.h"

namespace nrsfm {
namespace tools {

Status RunTrack(const CommandFlags& flags, std::ostream& out,
                std::ostream& progress) {
  if (flags.frames_dir.empty() == flags.video.empty()) {
    return Status::Error(
        "give one of --frames_dir (a folder of frames) and --video");
  }
  if (flags.output.empty()) return Status::Error("--output is required");
  FlagTargets targets;
  NRSFM_RETURN_IF_ERROR(ApplyFlags(flags, &targets));
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path output(flags.output);
  if (fs::exists(output, ec) && !fs::is_directory(output, ec)) {
    return Status::Error("--output '" + flags.output + "' is not a folder");
  }
  if (!flags.overwrite && fs::exists(output / kTrackOutputFile, ec)) {
    return Status::Error("--output '" + flags.output +
                         "' holds tracks already (use --overwrite to replace "
                         "them)");
  }

  track::FrameSource frames;
  NRSFM_RETURN_IF_ERROR(
      flags.frames_dir.empty()
          ? track::FrameSource::OpenVideo(flags.video, &frames)
          : track::FrameSource::OpenFolder(flags.frames_dir, &frames));
  track::FrameSource mask;
  if (!flags.mask.empty()) {
    NRSFM_RETURN_IF_ERROR(track::FrameSource::OpenFolder(flags.mask, &mask));
  }
  std::vector<track::Query> queries;
  if (!flags.queries.empty()) {
    NRSFM_RETURN_IF_ERROR(track::ReadQueries(flags.queries, &queries));
    if (queries.empty()) {
      return Status::Error(flags.queries + ": no query");
    }
  }
  track::Tracks tracks;
  const auto report = [&](int done, int all) {
    if (!flags.quiet) {
      progress << "track: " << done << " / " << all << " frames" << std::endl;
    }
  };
  NRSFM_RETURN_IF_ERROR(
      track::TrackPoints(&frames, flags.mask.empty() ? nullptr : &mask, queries,
                         targets.track, report, &tracks)
          .WithContext(flags.queries.empty() ? frames.name() : flags.queries));

  fs::create_directories(output, ec);
  if (ec) {
    return Status::Error("--output '" + flags.output +
                         "': cannot create the folder (" + ec.message() + ")");
  }
  NRSFM_RETURN_IF_ERROR(
      track::WriteTracksCsv((output / "tracks.csv").string(), tracks));
  NRSFM_RETURN_IF_ERROR(
      track::WriteTracksMat((output / kTrackOutputFile).string(), tracks));

  const nlohmann::json result = TrackSummaryJson(
      flags, frames.name(), frames.size().width, frames.size().height, tracks);
  const fs::path json_path = output / "result.json";
  std::ofstream json(json_path);
  json << result.dump(2) << "\n";
  json.close();
  if (!json) {
    return Status::Error(json_path.string() + ": cannot write the file");
  }
  std::vector<int> ranks = tracks.window_rank;
  std::sort(ranks.begin(), ranks.end());
  out << "tracked " << tracks.x.cols() << " points through " << tracks.x.rows()
      << " frames in " << tracks.seconds << " s"
      << (ranks.empty()
              ? std::string()
              : ", median rank " + std::to_string(ranks[ranks.size() / 2]))
      << ", " << track::PointsLost(tracks) << " lost at the end; wrote "
      << flags.output << "/{tracks.csv," << kTrackOutputFile
      << ",result.json}\n";
  return Status::OK();
}

}  // namespace tools
}  // namespace nrsfm
