#include "track/track_metrics.h"

#include <glog/logging.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace nrsfm {
namespace track {

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
  std::vector<double> sorted = errors;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2,
                   sorted.end());
  score.median_error = sorted[sorted.size() / 2];
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
