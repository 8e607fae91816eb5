// The flags of `nrsfm track` (and view's --frames_dir), rows of the one
// flag list NRSFM_COMMAND_FLAGS of tools/command_flags.h, which ends with
// them: same columns, same rules (a flag that sets an option takes its
// default from TrackOptions, track/tracks.h).
#ifndef NRSFM_TOOLS_TRACK_FLAGS_H_
#define NRSFM_TOOLS_TRACK_FLAGS_H_

#include "track/tracks.h"

#define NRSFM_TRACK_FLAGS(X)                                                  \
  X(std::string, frames_dir, "", kTool, NRSFM_SETS_NOTHING,                   \
    NRSFM_HELP({kTrack,                                                       \
                "folder of frames (images, in the order of the number in "    \
                "each name: the frame number of the outputs)."},              \
               {kView,                                                        \
                "folder of the frames (PNG/JPEG, one per frame, numbered as " \
                "track reads them), drawn under the 2D view."}))              \
  X(std::string, video, "", kTool, NRSFM_SETS_NOTHING,                        \
    NRSFM_HELP({kTrack, "video file (instead of --frames_dir)."}))            \
  X(std::string, queries, "", kTool, NRSFM_SETS_NOTHING,                      \
    NRSFM_HELP({kTrack,                                                       \
                "CSV point,frame,x,y: where each point starts (pixels, x "    \
                "right, y down); none = the tracker chooses points."}))       \
  X(std::string, mask, "", kTool, NRSFM_SETS_NOTHING,                         \
    NRSFM_HELP({kTrack,                                                       \
                "folder of object masks numbered as the frames (nonzero = "   \
                "the object)."}))                                             \
  X(std::string, track_method,                                                \
    ::nrsfm::track::TrackMethodName(::nrsfm::track::TrackOptions().method),   \
    kTracking, NRSFM_PARSES(track, method, ::nrsfm::track::ParseTrackMethod), \
    NRSFM_HELP({kTrack,                                                       \
                "rank: basis flow under the rank bound (Torresani 2001 "      \
                "§3.2); lk: pyramidal Lucas-Kanade alone."}))                 \
  X(int, patch_size, ::nrsfm::track::TrackOptions().patch_size, kTracking,    \
    NRSFM_SETS(track, patch_size),                                            \
    NRSFM_HELP({kTrack, "side of each point's square patch, pixels (odd)."})) \
  X(int, pyramid_levels, ::nrsfm::track::TrackOptions().pyramid_levels,       \
    kTracking, NRSFM_SETS(track, pyramid_levels),                             \
    NRSFM_HELP({kTrack, "pyramid levels above full resolution."}))            \
  X(int, window_frames, ::nrsfm::track::TrackOptions().window_frames,         \
    kTracking, NRSFM_SETS(track, window_frames),                              \
    NRSFM_HELP({kTrack,                                                       \
                "frames solved jointly under the rank bound; the templates "  \
                "are re-anchored at each window."}))                          \
  X(int, rank, ::nrsfm::track::TrackOptions().rank, kTracking,                \
    NRSFM_SETS(track, rank),                                                  \
    NRSFM_HELP({kTrack,                                                       \
                "rank of the track matrix; 0 = from the reliable tracks' "    \
                "singular values in each window."}))                          \
  X(double, rank_noise_px, ::nrsfm::track::TrackOptions().rank_noise_px,      \
    kTracking, NRSFM_SETS(track, rank_noise_px),                              \
    NRSFM_HELP({kTrack,                                                       \
                "the chosen rank fits the reliable tracks to this RMS, "      \
                "pixels."}))                                                  \
  X(int, max_rank, ::nrsfm::track::TrackOptions().max_rank, kTracking,        \
    NRSFM_SETS(track, max_rank),                                              \
    NRSFM_HELP({kTrack, "the largest rank chosen."}))                         \
  X(int, support_points, ::nrsfm::track::TrackOptions().num_support_points,   \
    kTracking, NRSFM_SETS(track, num_support_points),                         \
    NRSFM_HELP({kTrack,                                                       \
                "corners of the object region tracked in each window for "    \
                "the basis."}))                                               \
  X(int, auto_points, ::nrsfm::track::TrackOptions().num_auto_points,         \
    kTracking, NRSFM_SETS(track, num_auto_points),                            \
    NRSFM_HELP(                                                               \
        {kTrack, "without --queries: the points the tracker chooses."}))      \
  X(double, max_forward_backward_px,                                          \
    ::nrsfm::track::TrackOptions().max_forward_backward_px, kTracking,        \
    NRSFM_SETS(track, max_forward_backward_px),                               \
    NRSFM_HELP({kTrack,                                                       \
                "Lucas-Kanade's forward-backward error above which a step "   \
                "is lost, pixels."}))                                         \
  X(double, min_correlation, ::nrsfm::track::TrackOptions().min_correlation,  \
    kTracking, NRSFM_SETS(track, min_correlation),                            \
    NRSFM_HELP({kTrack,                                                       \
                "patch-template correlation below which a point is "          \
                "occluded."}))                                                \
  X(int, track_iterations, ::nrsfm::track::TrackOptions().iterations,         \
    kTracking, NRSFM_SETS(track, iterations),                                 \
    NRSFM_HELP({kTrack, "Gauss-Newton iterations per pyramid level."}))

#endif  // NRSFM_TOOLS_TRACK_FLAGS_H_
