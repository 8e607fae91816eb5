// How tracks are scored against labelled truth, the TAP-Vid way
// (docs/tracking.md): every labelled frame after a point's query frame
// counts; position errors only where the truth is visible.
//   median error   of the visible entries, pixels;
//   <delta>        the mean over the thresholds of the fraction of visible
//                  entries within that distance;
//   occlusion acc. how often the tracker's visible flag equals the truth's.
#ifndef NRSFM_TRACK_TRACK_METRICS_H_
#define NRSFM_TRACK_TRACK_METRICS_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/model/status.h"
#include "track/tracks.h"

namespace nrsfm {
namespace track {

// Labelled truth on the tracks' frames and points (same F × P layout):
// `labelled` 1 where a label exists, `visible` 1 where it sees the point.
struct TrackTruth {
  Eigen::MatrixXd x, y;
  Eigen::MatrixXi visible, labelled;
};

struct TrackScore {
  int num_visible = 0;   // visible labelled entries scored
  int num_labelled = 0;  // labelled entries scored (for the occlusion acc.)
  double median_error = 0.0;
  double delta = 0.0;
  double occlusion_accuracy = 0.0;
};

// Labels as TAP-Vid uses them, from a CSV `frame,point,x,y,visible` (or
// `frame,joint,…`; frame numbers of `frame_numbers`, pixels; rows with
// visible 0 carry no position): each labelled point is queried at its
// first visible label (`queries`, in increasing point order), and `truth`
// holds every label of those points on the frames of `frame_numbers`.
// Fails naming the file and row: another header, a frame not in
// frame_numbers, a point and frame twice, a point never visible.
Status ReadLabels(const std::string& path,
                  const std::vector<int>& frame_numbers,
                  std::vector<Query>* queries, TrackTruth* truth);

// Scores the points with select[p] true (all when empty) over the frames
// after each one's start; `thresholds` in pixels (TAP-Vid: 1, 2, 4, 8, 16
// at 256 × 256; scale them with the image). When `after_hidden` is true,
// only the frames after a point was first hidden in the truth count (the
// reappearing points).
TrackScore ScoreTracks(const Tracks& tracks, const TrackTruth& truth,
                       const std::vector<double>& thresholds,
                       const std::vector<bool>& select = {},
                       bool after_hidden = false);

}  // namespace track
}  // namespace nrsfm

#endif  // NRSFM_TRACK_TRACK_METRICS_H_
