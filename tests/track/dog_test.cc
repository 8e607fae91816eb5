// The labelled dog of ../shared/video (DAVIS frames, BADJA joints) scored by
// the TAP-Vid protocol (track/track_metrics.h). The plain Lucas–Kanade
// baseline reproduces the figure the tracker's issue quotes for it
// (<delta> .105, median 38.9 px; measured here .109 and 34.4 px): the
// labels, the queries and the scores are read as that measurement read them.
// Skipped without ../shared (fails with NRSFM_REQUIRE_SHARED=1).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "tests/test_util.h"
#include "track/track_metrics.h"
#include "track/tracker.h"

namespace nrsfm {
namespace track {
namespace {

TEST(DogTest, LucasKanadeReproducesThePublishedBaseline) {
  NRSFM_SKIP_WITHOUT_SHARED_DATA(datasets);
  const std::filesystem::path video =
      std::filesystem::path(datasets).parent_path() / "video";
  FrameSource frames;
  Status status = FrameSource::OpenFolder((video / "dog").string(), &frames);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(frames.num_frames(), 60);
  std::vector<Query> queries;
  TrackTruth truth;
  status = ReadLabels((video / "dog_joints_480p.csv").string(),
                      frames.frame_numbers(), &queries, &truth);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(queries.size(), 20u);  // every joint is visible somewhere
  EXPECT_EQ(queries[0].frame, 3);  // the first labelled frame

  TrackOptions options;
  options.method = TrackMethod::kLucasKanade;
  Tracks tracks;
  status = TrackPoints(&frames, nullptr, queries, options, nullptr, &tracks);
  ASSERT_TRUE(status.ok()) << status.message();
  const TrackScore score = ScoreTracks(tracks, truth, {4, 8, 16});
  EXPECT_EQ(score.num_visible, 171);  // visible labels after each query
  EXPECT_NEAR(score.delta, 0.105, 0.03);
  EXPECT_GT(score.median_error, 25.0);
  EXPECT_LT(score.median_error, 50.0);
}

TEST(DogTest, BadLabelsAreNamed) {
  const std::string dir = testing_util::MakeTempDir("labels");
  std::vector<Query> queries;
  TrackTruth truth;
  std::ofstream(dir + "/twice.csv")
      << "frame,joint,x,y,visible\n3,0,1,2,1\n3,0,1,2,1\n";
  EXPECT_NE(ReadLabels(dir + "/twice.csv", {3, 4}, &queries, &truth)
                .message()
                .find("row 2: point 0 is labelled twice in frame 3"),
            std::string::npos);
  std::ofstream(dir + "/frame.csv") << "frame,point,x,y,visible\n9,0,1,2,1\n";
  EXPECT_NE(ReadLabels(dir + "/frame.csv", {3, 4}, &queries, &truth)
                .message()
                .find("row 1: frame 9 is not one of the frames"),
            std::string::npos);
  std::ofstream(dir + "/good.csv")
      << "frame,point,x,y,visible\n4,7,5,6,1\n3,7,0,0,0\n3,2,1,1,0\n";
  ASSERT_TRUE(ReadLabels(dir + "/good.csv", {3, 4}, &queries, &truth).ok());
  ASSERT_EQ(queries.size(), 1u);  // point 2 is never visible
  EXPECT_EQ(queries[0].point, 7);
  EXPECT_EQ(queries[0].frame, 4);
  EXPECT_EQ(truth.labelled(0, 0), 1);
  EXPECT_EQ(truth.visible(0, 0), 0);
}

}  // namespace
}  // namespace track
}  // namespace nrsfm
