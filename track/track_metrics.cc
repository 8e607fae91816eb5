#include "track/track_metrics.h"

#include <glog/logging.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <utility>

#include "core/io/text_io.h"
#include "core/math/statistics.h"

namespace nrsfm {
namespace track {

Status ReadLabels(const std::string& path,
                  const std::vector<int>& frame_numbers,
                  std::vector<Query>* queries, TrackTruth* truth) {
  Eigen::MatrixXd table;
  Status status =
      ReadCsvTable(path, {"frame", "point", "x", "y", "visible"}, &table);
  if (!status.ok()) {
    const Status joint =
        ReadCsvTable(path, {"frame", "joint", "x", "y", "visible"}, &table);
    if (!joint.ok()) return status;
  }
  std::map<int, int> index_of;
  for (std::size_t i = 0; i < frame_numbers.size(); ++i) {
    index_of[frame_numbers[i]] = static_cast<int>(i);
  }
  std::map<int, Query> first;  // point id -> its first visible label
  std::set<std::pair<int, int>> seen;
  for (Eigen::Index r = 0; r < table.rows(); ++r) {
    const std::string where = path + ": row " + std::to_string(r + 1);
    const int frame = static_cast<int>(table(r, 0));
    const int point = static_cast<int>(table(r, 1));
    if (table(r, 0) != frame || table(r, 1) != point || point < 0) {
      return Status::Error(where + ": frame and point must be integers");
    }
    if (index_of.count(frame) == 0) {
      return Status::Error(where + ": frame " + std::to_string(frame) +
                           " is not one of the frames");
    }
    if (!seen.insert({point, frame}).second) {
      return Status::Error(where + ": point " + std::to_string(point) +
                           " is labelled twice in frame " +
                           std::to_string(frame));
    }
    if (table(r, 4) != 1) continue;
    const auto it = first.find(point);
    if (it == first.end() || index_of[frame] < index_of[it->second.frame]) {
      first[point] = {point, frame, table(r, 2), table(r, 3)};
    }
  }
  queries->clear();
  std::map<int, int> column;
  for (const auto& [point, query] : first) {
    column[point] = static_cast<int>(queries->size());
    queries->push_back(query);
  }
  const Eigen::Index frames = static_cast<Eigen::Index>(frame_numbers.size());
  const Eigen::Index points = static_cast<Eigen::Index>(queries->size());
  truth->x = Eigen::MatrixXd::Zero(frames, points);
  truth->y = Eigen::MatrixXd::Zero(frames, points);
  truth->visible = Eigen::MatrixXi::Zero(frames, points);
  truth->labelled = Eigen::MatrixXi::Zero(frames, points);
  for (Eigen::Index r = 0; r < table.rows(); ++r) {
    const auto it = column.find(static_cast<int>(table(r, 1)));
    if (it == column.end()) continue;  // never visible: not scored
    const int f = index_of[static_cast<int>(table(r, 0))], k = it->second;
    truth->labelled(f, k) = 1;
    truth->visible(f, k) = table(r, 4) == 1;
    truth->x(f, k) = table(r, 2);
    truth->y(f, k) = table(r, 3);
  }
  return Status::OK();
}

TrackScore ScoreTracks(const Tracks& tracks, const TrackTruth& truth,
                       const std::vector<double>& thresholds,
                       const std::vector<bool>& select, bool after_hidden) {
  CHECK_EQ(tracks.x.rows(), truth.x.rows());
  CHECK_EQ(tracks.x.cols(), truth.x.cols());
  std::vector<double> errors;
  int agree = 0;
  TrackScore score;
  for (Eigen::Index p = 0; p < tracks.x.cols(); ++p) {
    if (!select.empty() && !select[p]) continue;
    bool hidden_before = false;
    for (Eigen::Index f = tracks.start[p] + 1; f < tracks.x.rows(); ++f) {
      if (truth.labelled(f, p) && !truth.visible(f, p)) hidden_before = true;
      if (!truth.labelled(f, p)) continue;
      if (after_hidden && (!hidden_before || !truth.visible(f, p))) continue;
      ++score.num_labelled;
      agree += (tracks.visible(f, p) != 0) == (truth.visible(f, p) != 0);
      if (!truth.visible(f, p)) continue;
      errors.push_back(std::hypot(tracks.x(f, p) - truth.x(f, p),
                                  tracks.y(f, p) - truth.y(f, p)));
    }
  }
  score.num_visible = static_cast<int>(errors.size());
  if (score.num_labelled > 0) {
    score.occlusion_accuracy = static_cast<double>(agree) / score.num_labelled;
  }
  if (errors.empty()) return score;
  for (double& e : errors) {
    if (!std::isfinite(e)) e = std::numeric_limits<double>::infinity();
  }
  score.median_error = UpperMedian(errors, 0.0);
  double delta = 0.0;
  for (double threshold : thresholds) {
    delta += static_cast<double>(std::count_if(
                 errors.begin(), errors.end(),
                 [threshold](double e) { return e <= threshold; })) /
             errors.size();
  }
  score.delta = thresholds.empty() ? 0.0 : delta / thresholds.size();
  return score;
}

}  // namespace track
}  // namespace nrsfm
