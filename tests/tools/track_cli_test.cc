// `nrsfm track` as a user runs it: frames of the rendered cloth
// (track/synthetic_video.h) written as PNG files, tracked, then
// reconstructed from the output folder and scored against the 3-D truth
// beside the true tracks; and every bad input one line, exit 1, nothing
// written.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <regex>
#include <string>

#include "core/io/mat_io.h"
#include "tests/test_util.h"
#include "tests/tools/tool_test.h"
#include "track/synthetic_video.h"

namespace nrsfm {
namespace {

namespace fs = std::filesystem;

class TrackCliTest : public ToolTest {
 protected:
  TrackCliTest() : ToolTest("nrsfm_track_cli") {}

  void SetUp() override {
    ToolTest::SetUp();
    ASSERT_TRUE(
        track::RenderSyntheticVideo(track::SyntheticVideoOptions(), &video_)
            .ok());
    fs::create_directories(Path("frames"));
    for (std::size_t f = 0; f < video_.frames.size(); ++f) {
      char name[32];
      std::snprintf(name, sizeof(name), "/%04zu.png", f);
      ASSERT_TRUE(cv::imwrite(Path("frames") + name, video_.frames[f]));
    }
    std::ofstream queries(Path("queries.csv"));
    queries << "point,frame,x,y\n";
    for (Eigen::Index p = 0; p < video_.x.cols(); ++p) {
      queries << p << ",0," << video_.x(0, p) << "," << video_.y(0, p) << "\n";
    }
  }

  // The e3D that `reconstruct ... --truth` prints.
  static double PrintedE3D(const std::string& out) {
    std::smatch match;
    EXPECT_TRUE(std::regex_search(out, match, std::regex("e3D ([0-9.]+)")))
        << out;
    return match.empty() ? NAN : std::stod(match[1]);
  }

  track::SyntheticVideo video_;
};

TEST_F(TrackCliTest, FramesToTracksToShapes) {
  const auto tracked = Run(
      "track --frames_dir frames --queries queries.csv --output out --quiet");
  ASSERT_EQ(tracked.exit_code, 0) << tracked.err;
  EXPECT_NE(tracked.out.find("tracked 81 points through 60 frames"),
            std::string::npos)
      << tracked.out;
  const std::string csv =
      testing_util::ReadFileToString(Path("out/tracks.csv"));
  EXPECT_EQ(csv.rfind("frame,point,x,y,visible\n0,0,", 0), 0u)
      << csv.substr(0, 80);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 60 * 81);
  const nlohmann::json result = nlohmann::json::parse(
      testing_util::ReadFileToString(Path("out/result.json")));
  EXPECT_EQ(result["options"]["track_method"], "rank");
  EXPECT_EQ(result["frames"], 60);
  EXPECT_FALSE(result["window_rank"].empty());

  // The 3-D truth and the true tracks (hidden entries missing), as .mat.
  const int frames = static_cast<int>(video_.x.rows());
  const int points = static_cast<int>(video_.x.cols());
  Eigen::MatrixXd p3(3 * frames, points), w(2 * frames, points);
  for (int f = 0; f < frames; ++f) {
    for (int p = 0; p < points; ++p) {
      for (int i = 0; i < 3; ++i)
        p3(i * frames + f, p) = video_.shape(f, 3 * p + i);
      w(2 * f, p) = video_.visible(f, p) ? video_.x(f, p) : NAN;
      w(2 * f + 1, p) = video_.visible(f, p) ? video_.y(f, p) : NAN;
    }
  }
  ASSERT_TRUE(
      WriteMat(Path("truth.mat"), MatVersion::kV5, {{"P3_gt", p3, {}}}).ok());
  ASSERT_TRUE(
      WriteMat(Path("true_tracks.mat"), MatVersion::kV5, {{"W", w, {}}}).ok());
  const auto from_tracks = Run(
      "reconstruct --input out --K 3 --output rec --truth truth.mat --quiet");
  ASSERT_EQ(from_tracks.exit_code, 0) << from_tracks.err;
  const auto from_truth =
      Run("reconstruct --input true_tracks.mat --K 3 --output rec_true --truth "
          "truth.mat --quiet");
  ASSERT_EQ(from_truth.exit_code, 0) << from_truth.err;
  // End to end within 1.5 times the true tracks' e3D (camera frame;
  // measured .575 against .595: this slow 40° orbit is hard for the
  // reconstruction itself).
  EXPECT_LT(PrintedE3D(from_tracks.out), 1.5 * PrintedE3D(from_truth.out));
}

TEST_F(TrackCliTest, BadInputIsOneLineAndWritesNothing) {
  const struct {
    std::string args, message;
  } cases[] = {
      {"track --output o",
       "give one of --frames_dir (a folder of frames) and --video"},
      {"track --frames_dir frames --video v.mp4 --output o",
       "give one of --frames_dir"},
      {"track --frames_dir nowhere --output o",
       "nowhere: not a folder of frames"},
      {"track --video nowhere.mp4 --output o",
       "nowhere.mp4: no such video file"},
      // FFmpeg's own message on it is silenced: one line.
      {"track --video junk.mp4 --output o",
       "junk.mp4: cannot open the video (no decoder?)"},
      {"track --frames_dir frames", "--output is required"},
      {"track --frames_dir frames --queries bad_frame.csv --output o",
       "query of point 2: frame 75 is not one of frames's frames"},
      {"track --frames_dir frames --queries outside.csv --output o",
       "query of point 1: (330.000000, 10.000000) is outside the 320 x 240 "
       "image"},
      {"track --frames_dir frames --patch_size 4 --output o",
       "--patch_size: patch_size: 4"},
      {"track --frames_dir frames --track_method flow --output o",
       "unknown value \"flow\" (expected one of rank, lk)"},
  };
  std::ofstream(Path("bad_frame.csv")) << "point,frame,x,y\n2,75,10,10\n";
  std::ofstream(Path("junk.mp4")) << "not a video";
  std::ofstream(Path("outside.csv")) << "point,frame,x,y\n1,0,330,10\n";
  for (const auto& c : cases) {
    const auto run = Run(c.args);
    EXPECT_EQ(run.exit_code, 1) << c.args;
    EXPECT_NE(run.err.find(c.message), std::string::npos) << c.args << "\n"
                                                          << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1)
        << c.args << "\n"
        << run.err;
    EXPECT_FALSE(fs::exists(Path("o"))) << c.args;
  }
}

}  // namespace
}  // namespace nrsfm
