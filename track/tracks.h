// The tracker's options, its queries and its tracks, and their files
// (track/tracker.h tracks; nothing of OpenCV here, so the tools' options
// can name them).
#ifndef NRSFM_TRACK_TRACKS_H_
#define NRSFM_TRACK_TRACKS_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/model/status.h"

namespace nrsfm {
namespace track {

enum class TrackMethod { kRank, kLucasKanade };
// "rank", "lk"; the error lists them.
const char* TrackMethodName(TrackMethod method);
Status ParseTrackMethod(const std::string& name, TrackMethod* method);

struct TrackOptions {
  TrackMethod method = TrackMethod::kRank;
  // Side of the square patch of each point, pixels (odd, ≥ 5).
  int patch_size = 21;
  // Pyramid levels above the full resolution (coarse to fine), ≥ 0.
  int pyramid_levels = 3;
  // Frames solved jointly under the rank bound; each window starts at the
  // last frame of the previous one, where the templates are re-anchored.
  int window_frames = 20;
  // r, the rank of the track matrix; 0 = chosen in each window from the
  // reliable tracks' singular values.
  int rank = 0;
  // The chosen r is the least that fits the reliable tracks to this RMS,
  // pixels (their noise level), at most max_rank.
  double rank_noise_px = 0.5;
  int max_rank = 12;
  // Reliable points sought in each window (corners of the object region:
  // the mask, else the bounding box of the tracked points grown by a
  // quarter of its size on each side).
  int num_support_points = 200;
  // Without queries: the points chosen in the first frame (half corners,
  // half a grid of the object region: edges and weak texture too).
  int num_auto_points = 100;
  // Lucas–Kanade's forward–backward error above which a step is lost.
  double max_forward_backward_px = 1.0;
  // Normalised cross-correlation of patch and template below which a point
  // is judged occluded, in (-1, 1).
  double min_correlation = 0.7;
  // Gauss–Newton iterations of eq. 9 per pyramid level.
  int iterations = 8;

  // The first invalid field, named.
  Status Check() const;
};

// A point to track: it starts at frame number `frame` at (x, y).
struct Query {
  int point = 0;  // the point's id in the outputs
  int frame = 0;  // a frame number of the source
  double x = 0.0;
  double y = 0.0;
};

// Reads `point,frame,x,y` (a header line, then one row per point; point ids
// distinct integers ≥ 0, frame an integer). Fails naming the file and row.
Status ReadQueries(const std::string& path, std::vector<Query>* queries);

struct Tracks {
  std::vector<int> frame_numbers;  // F, of the source
  std::vector<int> point_ids;      // P
  std::vector<int> start;          // per point, the frame index of its query
  // F × P positions; NaN before the point's start.
  Eigen::MatrixXd x, y;
  // F × P: 1 where the tracker judges the point visible (0 before start).
  Eigen::MatrixXi visible;
  // Per window: its first frame index and the rank used (kRank).
  std::vector<int> window_start, window_rank;
  // Windows where too few points were reliable for a basis (Lucas–Kanade's
  // tracks were kept there).
  int windows_without_basis = 0;
  double seconds = 0.0;
};

// Points lost: tracked points not visible in the last frame.
int PointsLost(const Tracks& tracks);

// One image of a folder of frames: its path and frame number.
struct FrameFile {
  std::string path;
  int number = 0;
};

// The images of a folder of frames in the order of their numbers (track/
// frame_source.h says which files and how they are numbered); fails naming
// the folder or file: not a folder, no image, a name without a number, a
// number twice.
Status ListFrameFiles(const std::string& folder,
                      std::vector<FrameFile>* frames);

// tracks.csv: header `frame,point,x,y,visible`, one row per point and
// frame from the point's start on (frame numbers and point ids of the
// tracks, pixels; visible 0 where judged occluded or lost, with the
// predicted position).
Status WriteTracksCsv(const std::string& path, const Tracks& tracks);

// The tracks as `nrsfm reconstruct` reads them: a .mat file with W (2F × P,
// rows x, y of each frame, pixels) where occluded and not yet started
// entries are NaN, and `frame_numbers` (F × 1) and `point_ids` (1 × P).
Status WriteTracksMat(const std::string& path, const Tracks& tracks);

}  // namespace track
}  // namespace nrsfm

#endif  // NRSFM_TRACK_TRACKS_H_
