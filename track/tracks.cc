#include "track/tracks.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <utility>

#include "core/io/mat_io.h"
#include "core/io/text_io.h"
#include "core/model/enum_names.h"

namespace nrsfm {
namespace track {
namespace {

constexpr EnumName<TrackMethod> kTrackMethodNames[] = {
    {TrackMethod::kRank, "rank"}, {TrackMethod::kLucasKanade, "lk"}};

bool IsImageFile(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  for (const char* known : {".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff",
                            ".pgm", ".ppm", ".webp"}) {
    if (ext == known) return true;
  }
  return false;
}

// The last run of digits of the file's stem; false when it has none (or one
// too long for an int).
bool FrameNumberOf(const std::filesystem::path& path, int* number) {
  const std::string stem = path.stem().string();
  std::size_t end = stem.size();
  while (end > 0 && !std::isdigit(static_cast<unsigned char>(stem[end - 1]))) {
    --end;
  }
  std::size_t begin = end;
  while (begin > 0 &&
         std::isdigit(static_cast<unsigned char>(stem[begin - 1]))) {
    --begin;
  }
  if (begin == end || end - begin > 9) return false;
  *number = std::stoi(stem.substr(begin, end - begin));
  return true;
}

}  // namespace

Status ListFrameFiles(const std::string& folder,
                      std::vector<FrameFile>* frames) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) {
    return Status::Error(folder + ": not a folder of frames");
  }
  std::map<int, std::string> by_number;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end;
       it.increment(ec)) {
    if (!it->is_regular_file(ec) || !IsImageFile(it->path())) continue;
    int number = 0;
    const std::string file = it->path().string();
    if (!FrameNumberOf(it->path(), &number)) {
      return Status::Error(file + ": no frame number in the file name");
    }
    const auto [where, added] = by_number.emplace(number, file);
    if (!added) {
      return Status::Error(file + ": frame number " + std::to_string(number) +
                           " is also that of " + where->second);
    }
  }
  if (ec) return Status::Error(folder + ": cannot list the folder");
  if (by_number.empty()) {
    return Status::Error(folder +
                         ": no image in the folder (.png, .jpg, .jpeg, .bmp, "
                         ".tif, .tiff, .pgm, .ppm, .webp)");
  }
  frames->clear();
  for (const auto& [number, file] : by_number)
    frames->push_back({file, number});
  return Status::OK();
}

const char* TrackMethodName(TrackMethod method) {
  return NameOf(kTrackMethodNames, method);
}

Status ParseTrackMethod(const std::string& name, TrackMethod* method) {
  return ParseName(kTrackMethodNames, name, "track method", method);
}

Status TrackOptions::Check() const {
  if (std::string(TrackMethodName(method)) == "unknown") {
    return Status::Error("track method: not one of the TrackMethod values");
  }
  if (patch_size < 5 || patch_size % 2 == 0 || patch_size > 101) {
    return Status::Error("patch_size: " + std::to_string(patch_size) +
                         " (expected an odd number from 5 to 101)");
  }
  if (pyramid_levels < 0 || pyramid_levels > 8) {
    return Status::Error("pyramid_levels: " + std::to_string(pyramid_levels) +
                         " (expected 0 to 8)");
  }
  if (window_frames < 2) {
    return Status::Error("window_frames: " + std::to_string(window_frames) +
                         " (expected at least 2)");
  }
  if (max_rank < 3) {
    return Status::Error("max_rank: " + std::to_string(max_rank) +
                         " (expected at least 3)");
  }
  if (rank != 0 && (rank < 3 || rank > max_rank)) {
    return Status::Error("rank: " + std::to_string(rank) +
                         " (expected 0 = from the data, or 3 to max_rank " +
                         std::to_string(max_rank) + ")");
  }
  if (!(rank_noise_px > 0.0) || !std::isfinite(rank_noise_px)) {
    return Status::Error("rank_noise_px: expected a positive number");
  }
  if (num_support_points < 3) {
    return Status::Error(
        "num_support_points: " + std::to_string(num_support_points) +
        " (expected at least 3)");
  }
  if (num_auto_points < 1) {
    return Status::Error("num_auto_points: " + std::to_string(num_auto_points) +
                         " (expected at least 1)");
  }
  if (!(max_forward_backward_px > 0.0) ||
      !std::isfinite(max_forward_backward_px)) {
    return Status::Error("max_forward_backward_px: expected a positive number");
  }
  if (!(min_correlation > -1.0 && min_correlation < 1.0)) {
    return Status::Error("min_correlation: expected a number in (-1, 1)");
  }
  if (iterations < 1) {
    return Status::Error("iterations: " + std::to_string(iterations) +
                         " (expected at least 1)");
  }
  return Status::OK();
}

Status ReadQueries(const std::string& path, std::vector<Query>* queries) {
  Eigen::MatrixXd table;
  NRSFM_RETURN_IF_ERROR(
      ReadCsvTable(path, {"point", "frame", "x", "y"}, &table));
  std::vector<Query> result;
  std::set<int> ids;
  for (Eigen::Index row = 0; row < table.rows(); ++row) {
    const std::string where =
        path + ": row " + std::to_string(row + 1) + " of the queries";
    for (int c : {0, 1}) {
      const double v = table(row, c);
      if (!(std::isfinite(v) && v == std::floor(v) && std::abs(v) < 1e9)) {
        return Status::Error(where + ": " + (c == 0 ? "point" : "frame") +
                             " is not an integer");
      }
    }
    if (!std::isfinite(table(row, 2)) || !std::isfinite(table(row, 3))) {
      return Status::Error(where + ": x and y must be finite");
    }
    Query query;
    query.point = static_cast<int>(table(row, 0));
    query.frame = static_cast<int>(table(row, 1));
    query.x = table(row, 2);
    query.y = table(row, 3);
    if (query.point < 0) return Status::Error(where + ": point id below 0");
    if (!ids.insert(query.point).second) {
      return Status::Error(where + ": point " + std::to_string(query.point) +
                           " is queried twice");
    }
    result.push_back(query);
  }
  *queries = std::move(result);
  return Status::OK();
}

int PointsLost(const Tracks& tracks) {
  if (tracks.visible.rows() == 0) return 0;
  return static_cast<int>(tracks.visible.cols() -
                          tracks.visible.row(tracks.visible.rows() - 1).sum());
}

Status WriteTracksCsv(const std::string& path, const Tracks& tracks) {
  TextWriter writer;
  NRSFM_RETURN_IF_ERROR(writer.Open(path));
  writer.Text("frame,point,x,y,visible\n");
  for (Eigen::Index f = 0; f < tracks.x.rows(); ++f) {
    for (Eigen::Index p = 0; p < tracks.x.cols(); ++p) {
      if (f < tracks.start[p]) continue;
      writer.Int(tracks.frame_numbers[f]).Char(',').Int(tracks.point_ids[p]);
      writer.Char(',').Number(tracks.x(f, p)).Char(',').Number(tracks.y(f, p));
      writer.Char(',').Int(tracks.visible(f, p)).Char('\n');
    }
  }
  return writer.Close();
}

Status WriteTracksMat(const std::string& path, const Tracks& tracks) {
  const Eigen::Index frames = tracks.x.rows();
  const Eigen::Index points = tracks.x.cols();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Eigen::MatrixXd w = Eigen::MatrixXd::Constant(2 * frames, points, nan);
  for (Eigen::Index f = 0; f < frames; ++f) {
    for (Eigen::Index p = 0; p < points; ++p) {
      if (!tracks.visible(f, p)) continue;
      w(2 * f, p) = tracks.x(f, p);
      w(2 * f + 1, p) = tracks.y(f, p);
    }
  }
  Eigen::MatrixXd numbers(frames, 1), ids(1, points);
  for (Eigen::Index f = 0; f < frames; ++f)
    numbers(f) = tracks.frame_numbers[f];
  for (Eigen::Index p = 0; p < points; ++p) ids(p) = tracks.point_ids[p];
  return WriteMat(
      path, MatVersion::kV5,
      {{"W", w, {}}, {"frame_numbers", numbers, {}}, {"point_ids", ids, {}}});
}

}  // namespace track
}  // namespace nrsfm
