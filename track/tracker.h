// Point tracking through a sequence of frames (Torresani et al. 2001,
// §3.2–3.3: "basis flow"; docs/tracking.md).
//
// Positions are in pixels of the full-resolution frame, x right, y down,
// the centre of the top-left pixel at (0, 0). Each point starts at its own
// query (TAP-Vid's query-first convention) and is tracked forward from it.
//
// kRank, the default: the frames are solved in windows of window_frames;
// in each window the reliable points (pyramidal Lucas–Kanade with a
// forward–backward check, corners of the object region) give by SVD the r
// basis tracks Q̂ (eq. 8; r from their singular values, the least rank that
// explains them to rank_noise_px), and every point's track is Q̂ b_i with
// its r coefficients b_i solved from the Lucas–Kanade equations of all its
// frames at once (eq. 9), relative to its template (its patch in the
// window's first frame, re-anchored at each window), coarse to fine, frames
// whose appearance no longer matches the template left out (§3.3: they
// are occluded, and their position is the basis' prediction).
// kLucasKanade: OpenCV's calcOpticalFlowPyrLK frame to frame, the baseline.
//
// A point is visible where its patch matches the template (normalised
// cross-correlation ≥ min_correlation) and, for Lucas–Kanade, where the
// forward–backward error is at most max_forward_backward_px.
#ifndef NRSFM_TRACK_TRACKER_H_
#define NRSFM_TRACK_TRACKER_H_

#include <functional>
#include <vector>

#include "core/model/status.h"
#include "track/frame_source.h"
#include "track/tracks.h"

namespace nrsfm {
namespace track {

// Progress: called after each window with (frames done, frames in all).
using TrackProgress = std::function<void(int, int)>;

// Tracks `queries` (checked against the frames: a frame number the source
// does not have, a position outside the image, a point id twice: an error
// naming the query), or, when it is empty, points the tracker chooses in the
// first frame (inside `mask` when given). `mask`, when not null, is a frame
// source of the same numbers and size whose nonzero pixels are the object.
Status TrackPoints(FrameSource* frames, FrameSource* mask,
                   const std::vector<Query>& queries,
                   const TrackOptions& options, const TrackProgress& progress,
                   Tracks* tracks);

}  // namespace track
}  // namespace nrsfm

#endif  // NRSFM_TRACK_TRACKER_H_
