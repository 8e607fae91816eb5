// The tracker on the rendered cloth of track/synthetic_video.h (exact
// truth): the rank bound carries the edge-only points and the points that
// reappear after the disc, where Lucas–Kanade alone fails (Torresani et al.
// 2001, §3.2–3.3). Bounds from measured values (bench/track/track_bench.cc
// --suite=synthetic, seed 1: rank edges 1.60 px, reappearing 1.94 px,
// occlusion accuracy .961; Lucas–Kanade 9.14 px, 66.3 px, .870).
#include "track/tracker.h"

#include <gtest/gtest.h>

#include "track/synthetic_video.h"
#include "track/track_metrics.h"

namespace nrsfm {
namespace track {
namespace {

struct TrackRun {
  TrackScore corners, edges, reappearing, all;
  Tracks tracks;
};

class TrackerTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    SyntheticVideoOptions options;  // seed 1
    ASSERT_TRUE(RenderSyntheticVideo(options, &video_).ok());
  }

  static TrackRun Track(TrackMethod method) {
    std::vector<Query> queries;
    TrackTruth truth;
    QueriesAndTruth(video_, &queries, &truth);
    FrameSource source;
    EXPECT_TRUE(FrameSource::FromImages(video_.frames, &source).ok());
    TrackOptions options;
    options.method = method;
    TrackRun run;
    const Status status =
        TrackPoints(&source, nullptr, queries, options, nullptr, &run.tracks);
    EXPECT_TRUE(status.ok()) << status.message();
    std::vector<bool> corners, edges;
    for (const Query& query : queries) {
      const int p = query.point;
      corners.push_back(video_.texture[p] == Texture::kCorners);
      edges.push_back(video_.texture[p] == Texture::kEdges);
    }
    run.corners = ScoreTracks(run.tracks, truth, {1, 2, 4}, corners);
    run.edges = ScoreTracks(run.tracks, truth, {1, 2, 4}, edges);
    run.reappearing = ScoreTracks(run.tracks, truth, {1, 2, 4}, {}, true);
    run.all = ScoreTracks(run.tracks, truth, {1, 2, 4});
    return run;
  }

  static SyntheticVideo video_;
};

SyntheticVideo TrackerTest::video_;

TEST_F(TrackerTest, TheRankBoundCarriesEdgesAndReappearingPoints) {
  const TrackRun lk = Track(TrackMethod::kLucasKanade);
  const TrackRun rank = Track(TrackMethod::kRank);
  // The scenario holds what it claims: the disc hides points that come back.
  ASSERT_GT(rank.reappearing.num_visible, 500);
  // Edge-only points: Lucas–Kanade slides along the stripes (9.1 px).
  EXPECT_GT(lk.edges.median_error, 5.0);
  EXPECT_LT(rank.edges.median_error, 2.5);
  EXPECT_GT(rank.edges.delta, lk.edges.delta + 0.15);  // .586 against .312
  // After the occlusion Lucas–Kanade is lost (66 px); the basis brings the
  // points back.
  EXPECT_GT(lk.reappearing.median_error, 20.0);
  EXPECT_LT(rank.reappearing.median_error, 3.0);
  // Corners: both track; the rank bound no worse (0.91 against 1.17 px).
  EXPECT_LT(rank.corners.median_error, 1.3);
  EXPECT_LT(rank.corners.median_error, lk.corners.median_error + 0.1);
  // Occlusion: the disc is seen (.961 against .870).
  EXPECT_GT(rank.all.occlusion_accuracy, 0.92);
  EXPECT_GT(rank.all.occlusion_accuracy, lk.all.occlusion_accuracy);
  ASSERT_FALSE(rank.tracks.window_rank.empty());
  for (int r : rank.tracks.window_rank) {
    EXPECT_GE(r, 3);
    EXPECT_LE(r, TrackOptions().max_rank);
  }
}

TEST_F(TrackerTest, BadQueriesAndOptionsAreErrors) {
  FrameSource source;
  ASSERT_TRUE(FrameSource::FromImages(video_.frames, &source).ok());
  Tracks tracks;
  Status status = TrackPoints(&source, nullptr, {{4, 99, 10, 10}},
                              TrackOptions(), nullptr, &tracks);
  EXPECT_NE(status.message().find("query of point 4: frame 99 is not one of"),
            std::string::npos)
      << status.message();
  status = TrackPoints(&source, nullptr, {{4, 0, 400, 10}}, TrackOptions(),
                       nullptr, &tracks);
  EXPECT_NE(status.message().find("is outside the 320 x 240 image"),
            std::string::npos)
      << status.message();
  TrackOptions options;
  options.patch_size = 20;
  EXPECT_NE(TrackPoints(&source, nullptr, {}, options, nullptr, &tracks)
                .message()
                .find("patch_size: 20"),
            std::string::npos);
  options = TrackOptions();
  options.rank = 2;
  EXPECT_NE(options.Check().message().find("rank: 2"), std::string::npos);
}

TEST_F(TrackerTest, WithoutQueriesItChoosesPointsAndKeepsThemInView) {
  FrameSource source;
  ASSERT_TRUE(FrameSource::FromImages(video_.frames, &source).ok());
  TrackOptions options;
  options.num_auto_points = 40;
  Tracks tracks;
  ASSERT_TRUE(
      TrackPoints(&source, nullptr, {}, options, nullptr, &tracks).ok());
  EXPECT_EQ(tracks.x.cols(), 40);
  EXPECT_EQ(tracks.x.rows(), static_cast<Eigen::Index>(video_.frames.size()));
  EXPECT_TRUE(tracks.x.allFinite());
  for (Eigen::Index p = 0; p < tracks.x.cols(); ++p) {
    EXPECT_GE(tracks.x.col(p).minCoeff(), -1.0);
    EXPECT_LE(tracks.x.col(p).maxCoeff(), 320.0);
  }
}

}  // namespace
}  // namespace track
}  // namespace nrsfm
