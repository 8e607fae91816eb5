// A synthetic video with exact truth for the tracker (docs/tracking.md):
// a textured cloth sheet that bends in K smooth modes and turns before an
// orthographic camera, rendered by a small rasteriser with a depth buffer,
// and a textured disc that passes in front of it (an occlusion the points
// reappear from). The sheet's texture has three bands across it: 2-D
// texture (blobs: corners), 1-D texture (stripes: edges only, the aperture
// problem) and weak texture (low-contrast noise); every tracked point
// knows its band. Positions are pixels of the frame, x right, y down, the
// centre of the top-left pixel at (0, 0).
#ifndef NRSFM_TRACK_SYNTHETIC_VIDEO_H_
#define NRSFM_TRACK_SYNTHETIC_VIDEO_H_

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "core/model/status.h"
#include "track/track_metrics.h"

namespace nrsfm {
namespace track {

struct SyntheticVideoOptions {
  int frames = 60;
  int width = 320;   // pixels
  int height = 240;  // pixels
  // Tracked points: a points_per_side × points_per_side grid on the sheet.
  int points_per_side = 9;
  int num_bases = 2;         // bending modes (K − 1 of the shape model)
  double bending = 0.25;     // mode amplitude, a fraction of the sheet size
  double rotation_deg = 40;  // peak-to-peak turn about the vertical axis
  double noise_grey = 2.0;   // Gaussian image noise, grey levels
  bool occluder = true;      // the disc that passes in front
  std::uint64_t seed = 1;

  Status Check() const;
};

// What a tracked point's patch holds.
enum class Texture { kCorners = 0, kEdges = 1, kWeak = 2 };

struct SyntheticVideo {
  std::vector<cv::Mat> frames;   // F, 8-bit grey, height × width
  Eigen::MatrixXd x, y;          // F × P true positions
  Eigen::MatrixXi visible;       // F × P: 1 = in view (not hidden)
  std::vector<Texture> texture;  // P
  // F × 3P: each frame's points in the camera frame (pixels; x, y as the
  // image, z away from the camera), [X_0 Y_0 Z_0 X_1 …]: the 3-D truth.
  Eigen::MatrixXd shape;
};

Status RenderSyntheticVideo(const SyntheticVideoOptions& options,
                            SyntheticVideo* video);

// The video's scoring set-up: every point visible in frame 0 queried there
// (`queries`), and the truth of those points in their order (`truth`,
// every entry labelled; track/track_metrics.h).
void QueriesAndTruth(const SyntheticVideo& video, std::vector<Query>* queries,
                     TrackTruth* truth);

}  // namespace track
}  // namespace nrsfm

#endif  // NRSFM_TRACK_SYNTHETIC_VIDEO_H_
