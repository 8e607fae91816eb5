// nrsfm_track_bench: the tracker's benchmark (docs/tracking.md).
//   --suite=synthetic  the rendered cloth of track/synthetic_video.h, several
//                      seeds: rank-constrained tracking against Lucas–Kanade
//                      on the corner, edge, weak-texture and reappearing
//                      points; then end to end, the tracks reconstructed
//                      (default options) against reconstructing the true
//                      tracks, e3D in the camera frame.
//   --suite=speed      100 points through 100 frames of 854 × 480, decoded
//                      from PNG files, both methods.
//   --suite=dog        ../shared/video (--video_dir): the labelled dog, the
//                      TAP-Vid protocol; skipped when absent.
//   --suite=all        all three.
#include <gflags/gflags.h>
#include <glog/logging.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "core/eval/metrics.h"
#include "core/io/text_io.h"
#include "solvers/pipeline/reconstruct.h"
#include "track/synthetic_video.h"
#include "track/track_metrics.h"
#include "track/tracker.h"

DEFINE_string(suite, "all", "synthetic, speed, dog or all");
DEFINE_int32(seeds, 3, "synthetic: seeds 1 … N");
DEFINE_string(video_dir, "../shared/video",
              "the labelled dog (dog/, dog_joints_480p.csv)");
DEFINE_string(scratch, "",
              "speed: folder for the PNG frames (default: a temporary one)");

namespace {

using nrsfm::track::FrameSource;
using nrsfm::track::Query;
using nrsfm::track::TrackMethod;
using nrsfm::track::TrackOptions;
using nrsfm::track::Tracks;
using nrsfm::track::TrackScore;
using nrsfm::track::TrackTruth;

void Die(const nrsfm::Status& status) {
  if (status.ok()) return;
  std::fprintf(stderr, "nrsfm_track_bench: %s\n", status.message().c_str());
  std::exit(1);
}

const char* MethodName(TrackMethod method) {
  return nrsfm::track::TrackMethodName(method);
}

// e3D (camera frame) of the default reconstruction of `w` (2F × P, NaN
// missing) at K against the truth shapes.
double ReconstructE3D(const Eigen::MatrixXd& w, int num_bases,
                      const std::vector<Eigen::Matrix3Xd>& truth) {
  nrsfm::Measurements m;
  m.num_frames = static_cast<int>(w.rows() / 2);
  m.num_points = static_cast<int>(w.cols());
  m.W = w;
  m.visible.resize(m.num_frames, m.num_points);
  for (int f = 0; f < m.num_frames; ++f) {
    for (int p = 0; p < m.num_points; ++p) {
      m.visible(f, p) = std::isfinite(w(2 * f, p));
      if (!m.visible(f, p)) m.W(2 * f, p) = m.W(2 * f + 1, p) = 0.0;
    }
  }
  nrsfm::ReconstructOptions options;
  options.start.num_bases = num_bases;
  nrsfm::ReconstructResult result;
  Die(nrsfm::Reconstruct(options, m, &result));
  // Points the reconstruction left out (seen in too few views) are NaN:
  // scored on the others.
  std::vector<Eigen::Matrix3Xd> estimate, kept_truth;
  std::vector<int> kept;
  for (int p = 0; p < m.num_points; ++p) {
    if (result.model.ShapeInCamera(0, 0).col(p).allFinite()) kept.push_back(p);
  }
  for (int f = 0; f < m.num_frames; ++f) {
    const Eigen::Matrix3Xd shape = result.model.ShapeInCamera(f, 0);
    estimate.emplace_back(3, kept.size());
    kept_truth.emplace_back(3, kept.size());
    for (std::size_t k = 0; k < kept.size(); ++k) {
      estimate.back().col(k) = shape.col(kept[k]);
      kept_truth.back().col(k) = truth[f].col(kept[k]);
    }
  }
  return nrsfm::ComputeE3D(kept_truth, estimate);
}

void Synthetic() {
  std::printf(
      "## synthetic cloth (320 x 240, 60 frames, 81 points, 2 grey levels "
      "noise, a disc passing in front)\n\n");
  std::printf(
      "| seed | method | corners median / <d> | edges median / <d> | weak "
      "median / <d> | reappearing median / <d> | occlusion acc. | e3D tracked "
      "(true tracks) |\n|---|---|---|---|---|---|---|---|\n");
  for (int seed = 1; seed <= FLAGS_seeds; ++seed) {
    nrsfm::track::SyntheticVideoOptions so;
    so.seed = seed;
    nrsfm::track::SyntheticVideo video;
    Die(nrsfm::track::RenderSyntheticVideo(so, &video));
    const int frames = so.frames;
    std::vector<Query> queries;
    TrackTruth truth;
    nrsfm::track::QueriesAndTruth(video, &queries, &truth);
    const int points = static_cast<int>(queries.size());
    std::vector<bool> group[3];
    std::vector<Eigen::Matrix3Xd> shapes(frames, Eigen::Matrix3Xd(3, points));
    Eigen::MatrixXd true_w(2 * frames, points);
    for (int k = 0; k < points; ++k) {
      const int p = queries[k].point;
      for (int g = 0; g < 3; ++g)
        group[g].push_back(static_cast<int>(video.texture[p]) == g);
      for (int f = 0; f < frames; ++f) {
        shapes[f].col(k) = video.shape.block<1, 3>(f, 3 * p).transpose();
        const bool seen = video.visible(f, p);
        true_w(2 * f, k) = seen ? video.x(f, p) : NAN;
        true_w(2 * f + 1, k) = seen ? video.y(f, p) : NAN;
      }
    }
    const double true_e3d = ReconstructE3D(true_w, 3, shapes);
    for (TrackMethod method : {TrackMethod::kLucasKanade, TrackMethod::kRank}) {
      FrameSource source;
      Die(FrameSource::FromImages(video.frames, &source));
      TrackOptions options;
      options.method = method;
      Tracks tracks;
      Die(nrsfm::track::TrackPoints(&source, nullptr, queries, options, nullptr,
                                    &tracks));
      std::printf("| %d | %s |", seed, MethodName(method));
      for (int g = 0; g < 3; ++g) {
        const TrackScore s =
            nrsfm::track::ScoreTracks(tracks, truth, {1, 2, 4}, group[g]);
        std::printf(" %.2f / %.3f |", s.median_error, s.delta);
      }
      const TrackScore re =
          nrsfm::track::ScoreTracks(tracks, truth, {1, 2, 4}, {}, true);
      const TrackScore all =
          nrsfm::track::ScoreTracks(tracks, truth, {1, 2, 4});
      Eigen::MatrixXd w(2 * frames, points);
      for (int f = 0; f < frames; ++f) {
        for (int k = 0; k < points; ++k) {
          w(2 * f, k) = tracks.visible(f, k) ? tracks.x(f, k) : NAN;
          w(2 * f + 1, k) = tracks.visible(f, k) ? tracks.y(f, k) : NAN;
        }
      }
      std::printf(" %.2f / %.3f | %.3f | %.4f (%.4f) |\n", re.median_error,
                  re.delta, all.occlusion_accuracy,
                  ReconstructE3D(w, 3, shapes), true_e3d);
      std::fflush(stdout);
    }
  }
}

void Speed() {
  nrsfm::track::SyntheticVideoOptions so;
  so.frames = 100;
  so.width = 854;
  so.height = 480;
  so.points_per_side = 10;
  nrsfm::track::SyntheticVideo video;
  Die(nrsfm::track::RenderSyntheticVideo(so, &video));
  namespace fs = std::filesystem;
  const fs::path dir = FLAGS_scratch.empty() ? fs::temp_directory_path() /
                                                   "nrsfm_track_bench_frames"
                                             : fs::path(FLAGS_scratch);
  fs::create_directories(dir);
  for (int f = 0; f < so.frames; ++f) {
    char name[32];
    std::snprintf(name, sizeof(name), "%05d.png", f);
    cv::imwrite((dir / name).string(), video.frames[f]);
  }
  std::vector<Query> queries;
  for (int p = 0; p < video.x.cols(); ++p)
    queries.push_back({p, 0, video.x(0, p), video.y(0, p)});
  std::printf(
      "## speed: %zu points, %d frames of 854 x 480 PNG (%s)\n\n| method | "
      "seconds (decoding included) |\n|---|---|\n",
      queries.size(), so.frames, dir.string().c_str());
  for (TrackMethod method : {TrackMethod::kLucasKanade, TrackMethod::kRank}) {
    FrameSource source;
    const auto start = std::chrono::steady_clock::now();
    Die(FrameSource::OpenFolder(dir.string(), &source));
    TrackOptions options;
    options.method = method;
    Tracks tracks;
    Die(nrsfm::track::TrackPoints(&source, nullptr, queries, options, nullptr,
                                  &tracks));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
            .count();
    std::printf("| %s | %.2f |\n", MethodName(method), seconds);
  }
  if (FLAGS_scratch.empty()) fs::remove_all(dir);
}

void Dog() {
  namespace fs = std::filesystem;
  const fs::path dir(FLAGS_video_dir);
  const fs::path labels_file = dir / "dog_joints_480p.csv";
  if (!fs::exists(labels_file)) {
    std::printf("## dog: skipped (%s not found)\n",
                labels_file.string().c_str());
    return;
  }
  FrameSource source;
  Die(FrameSource::OpenFolder((dir / "dog").string(), &source));
  std::vector<Query> queries;
  TrackTruth truth;
  Die(nrsfm::track::ReadLabels(labels_file.string(), source.frame_numbers(),
                               &queries, &truth));
  const int frames = source.num_frames();
  const int points = static_cast<int>(queries.size());
  std::printf(
      "## dog (%d joints, %d frames; TAP-Vid: <d> over 4, 8, 16 px)\n\n| "
      "method | <d> | median error px | visibility acc. | seconds "
      "|\n|---|---|---|---|---|\n",
      points, frames);
  for (TrackMethod method : {TrackMethod::kLucasKanade, TrackMethod::kRank}) {
    TrackOptions options;
    options.method = method;
    Tracks tracks;
    Die(nrsfm::track::TrackPoints(&source, nullptr, queries, options, nullptr,
                                  &tracks));
    const TrackScore s = nrsfm::track::ScoreTracks(tracks, truth, {4, 8, 16});
    std::printf("| %s | %.3f | %.1f | %.3f | %.2f |\n", MethodName(method),
                s.delta, s.median_error, s.occlusion_accuracy, tracks.seconds);
  }
}

}  // namespace

int main(int argc, char** argv) {
  FLAGS_logtostderr = true;
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  google::InitGoogleLogging(argv[0]);
  const std::string suite = FLAGS_suite;
  if (suite != "all" && suite != "synthetic" && suite != "speed" &&
      suite != "dog") {
    std::fprintf(stderr,
                 "nrsfm_track_bench: --suite: unknown value \"%s\" (expected "
                 "one of synthetic, speed, dog, all)\n",
                 suite.c_str());
    return 2;
  }
  if (suite == "all" || suite == "synthetic") Synthetic();
  if (suite == "all" || suite == "speed") Speed();
  if (suite == "all" || suite == "dog") Dog();
  return 0;
}
