// Detector keypoints through the real `nrsfm` binary: COCO results files and
// OpenPose folders that the tests write from known 3-D sequences seen as
// pixels (v down), with detector scores, some below --min_confidence, and
// frames with no person. They reconstruct like the same W given as a .mat
// file, score against the truth in the pixels' camera frame, and weighting
// by the scores (--confidence_weights) beats the unweighted run when the
// low-score keypoints are the noisy ones. Bad files get one error line.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "core/io/ground_truth.h"
#include "core/io/mat_io.h"
#include "core/io/read_measurements.h"
#include "core/io/result_reader.h"
#include "core/synthetic/synthetic.h"
#include "tests/test_util.h"
#include "tests/tools/tool_test.h"

namespace nrsfm {
namespace {

namespace fs = std::filesystem;

using RunResult = testing_util::CommandResult;

// A sequence as a detector would see it: the truth's camera-frame shapes X_t
// seen by an image whose v points down, in pixels: u = cu + s x,
// v = cv − s y. That camera is the truth's turned by 180° about its x axis,
// so the truth in the pixels' camera frame (x right, y down, z away from
// the camera) is s (x, −y, −z).
struct PixelSequence {
  Eigen::MatrixXd w;                    // 2F × P, pixels, noise-free
  std::vector<Eigen::Matrix3Xd> truth;  // camera frame of the pixels, pixels
};

PixelSequence ToPixels(const std::vector<Eigen::Matrix3Xd>& camera_frame,
                       double scale) {
  const int frames = static_cast<int>(camera_frame.size());
  const int points = static_cast<int>(camera_frame[0].cols());
  PixelSequence s;
  s.w.resize(2 * frames, points);
  for (int t = 0; t < frames; ++t) {
    Eigen::Matrix3Xd x = scale * camera_frame[t];
    x.row(1) *= -1.0;
    x.row(2) *= -1.0;
    s.w.row(2 * t) = (x.row(0).array() + 320.0).matrix();
    s.w.row(2 * t + 1) = (x.row(1).array() + 240.0).matrix();
    s.truth.push_back(x);
  }
  return s;
}

// Writes `truth` as P3_gt (3F × P, rows x of every frame, then y, then z),
// for --truth.
void WriteTruth(const std::string& path,
                const std::vector<Eigen::Matrix3Xd>& truth) {
  const int frames = static_cast<int>(truth.size());
  Eigen::MatrixXd p3(3 * frames, truth[0].cols());
  for (int t = 0; t < frames; ++t) {
    for (int i = 0; i < 3; ++i) p3.row(i * frames + t) = truth[t].row(i);
  }
  ASSERT_TRUE(WriteMat(path, MatVersion::kV5, {{"P3_gt", p3, {}}}).ok());
}

// The keypoints of frame t as [x, y, score, …].
nlohmann::json Triples(const Eigen::MatrixXd& w, const Eigen::ArrayXXd& score,
                       int t) {
  nlohmann::json values = nlohmann::json::array();
  for (int p = 0; p < w.cols(); ++p) {
    values.push_back(w(2 * t, p));
    values.push_back(w(2 * t + 1, p));
    values.push_back(score(t, p));
  }
  return values;
}

// A COCO results file: one entry per frame (image_id = 1 + t) except the
// frames in `no_person`, entries in reverse order (the reader sorts them).
void WriteCoco(const std::string& path, const Eigen::MatrixXd& w,
               const Eigen::ArrayXXd& score, const std::set<int>& no_person) {
  nlohmann::json entries = nlohmann::json::array();
  for (int t = static_cast<int>(w.rows() / 2) - 1; t >= 0; --t) {
    if (no_person.count(t) > 0) continue;
    entries.push_back({{"image_id", 1 + t},
                       {"category_id", 1},
                       {"keypoints", Triples(w, score, t)},
                       {"score", 0.9}});
  }
  std::ofstream(path) << entries.dump();
}

// An OpenPose folder: frame_<t>_keypoints.json (no zero padding: the reader
// orders the names naturally), "people": [] in the frames in `no_person`.
void WriteOpenPose(const std::string& dir, const Eigen::MatrixXd& w,
                   const Eigen::ArrayXXd& score,
                   const std::set<int>& no_person) {
  fs::create_directories(dir);
  for (int t = 0; t < w.rows() / 2; ++t) {
    nlohmann::json frame = {{"version", 1.3},
                            {"people", nlohmann::json::array()}};
    if (no_person.count(t) == 0) {
      frame["people"].push_back(
          {{"person_id", {-1}},
           {"pose_keypoints_2d", Triples(w, score, t)},
           {"face_keypoints_2d", nlohmann::json::array()},
           {"hand_left_keypoints_2d", nlohmann::json::array()},
           {"hand_right_keypoints_2d", nlohmann::json::array()}});
    }
    std::ofstream(dir + "/frame_" + std::to_string(t) + "_keypoints.json")
        << frame.dump();
  }
}

class KeypointTest : public ToolTest {
 protected:
  KeypointTest() : ToolTest("nrsfm_keypoint") {}
  nlohmann::json Result(const std::string& out) {
    return nlohmann::json::parse(
        testing_util::ReadFileToString(Path(out + "/result.json")));
  }
  // Camera 0's points of a result directory.
  GroundTruth Points(const std::string& out) {
    GroundTruth points;
    EXPECT_TRUE(ReadPointsCameraCsv(Path(out), 0, &points).ok());
    return points;
  }
  // `nrsfm <args>` fails with exit code 1 and one error line holding `needle`.
  void ExpectError(const std::string& args, const std::string& needle) {
    const RunResult r = Run(args);
    EXPECT_EQ(r.exit_code, 1) << args;
    EXPECT_NE(r.err.find(needle), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.find("Check failed"), std::string::npos) << r.err;
  }
};

// Largest difference between two results' points, NaN where both are NaN.
double MaxDifference(const GroundTruth& a, const GroundTruth& b) {
  EXPECT_EQ(a.NumFrames(), b.NumFrames());
  double largest = 0.0;
  for (int t = 0; t < a.NumFrames() && t < b.NumFrames(); ++t) {
    const Eigen::ArrayXXd x = a.points_in_camera[t].array(),
                          y = b.points_in_camera[t].array();
    EXPECT_TRUE((x.isNaN() == y.isNaN()).all()) << "frame " << t;
    largest =
        std::max(largest, (x.isNaN()).select(0.0, x - y).abs().maxCoeff());
  }
  return largest;
}

// pickup (F = 357, P = 41; its first 60 frames under the sanitizers, where
// the reconstruction stops after 5 iterations and is not scored: its
// accuracy is a release-build check, its code paths run there too) seen
// as 500-pixel keypoints with 0.5 px noise and scores in [0.3, 1], 3 % of the
// keypoints at 0.05 (below --min_confidence 0.1), three frames with no
// person. The COCO file and the OpenPose folder
// read as the same W as the one written (NaN where missing); the COCO file
// reconstructs with the published K = 12, leaving the three frames out, at
// the accuracy of the .mat file (README: e3D .0250 object frame, .0242
// camera frame, noise-free and complete), scored against the truth in the
// pixels' camera frame; the OpenPose folder goes through the tool too.
TEST_F(KeypointTest, PickupAsCocoResultsAndOpenPoseFolder) {
  NRSFM_SKIP_WITHOUT_SHARED_DATA(shared);
  GroundTruth pickup;
  ASSERT_TRUE(ReadGroundTruth(shared + "/pickup.mat", "", &pickup).ok());
  pickup.points_in_camera.resize(testing_util::kSanitizedBuild ? 60 : 357);
  double extent = 0.0;
  for (const Eigen::Matrix3Xd& x : pickup.points_in_camera) {
    extent = std::max(extent, (x.topRows<2>().rowwise().maxCoeff() -
                               x.topRows<2>().rowwise().minCoeff())
                                  .maxCoeff());
  }
  const PixelSequence s = ToPixels(pickup.points_in_camera, 500.0 / extent);
  const int frames = pickup.NumFrames(), points = pickup.NumPoints();
  std::mt19937 rng(29);
  std::normal_distribution<double> noise(0.0, 0.5);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Eigen::ArrayXXd score(frames, points);
  Eigen::MatrixXd w = s.w, w_missing = s.w;
  for (int t = 0; t < frames; ++t) {
    for (int p = 0; p < points; ++p) {
      w(2 * t, p) += noise(rng);
      w(2 * t + 1, p) += noise(rng);
      score(t, p) = uniform(rng) < 0.03 ? 0.05 : 0.3 + 0.7 * uniform(rng);
      w_missing.block<2, 1>(2 * t, p) =
          score(t, p) < 0.1 ? Eigen::Vector2d::Constant(NAN)
                            : Eigen::Vector2d(w.block<2, 1>(2 * t, p));
    }
  }
  const std::set<int> no_person = {30, 31, 50};
  for (int t : no_person) w_missing.middleRows(2 * t, 2).setConstant(NAN);
  WriteCoco(Path("keypoints.json"), w, score, no_person);
  WriteOpenPose(Path("openpose"), w, score, no_person);
  WriteTruth(Path("truth.mat"), s.truth);

  // Both read as W, to the bit.
  InputOptions input;
  input.keypoints.min_confidence = 0.1;
  for (const char* name : {"keypoints.json", "openpose"}) {
    Measurements m;
    InputDetails details;
    ASSERT_TRUE(ReadMeasurements(Path(name), input, &m, &details).ok()) << name;
    ASSERT_EQ(m.W.rows(), w_missing.rows());
    EXPECT_TRUE((m.W.array() == w_missing.array() ||
                 (m.W.array().isNaN() && w_missing.array().isNaN()))
                    .all())
        << name;
    EXPECT_EQ(m.NumVisible(), (w_missing.array().isNaN() == false).count() / 2)
        << name;
    EXPECT_TRUE(
        (details.confidence.isNaN() || details.confidence == score).all())
        << name;
  }

  RunResult r = Run(
      "reconstruct --input keypoints.json --K 12 --min_confidence 0.1 --output "
      "o "
      "--truth truth.mat --quiet" +
      std::string(testing_util::kSanitizedBuild ? " --max_iterations 5" : ""));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const std::string no_person_warning =
      "3 of " + std::to_string(frames) +
      " frames have no person, their points are missing (";
  EXPECT_NE(
      r.out.find("warning: " + no_person_warning + "image_id 31, 32, 51)"),
      std::string::npos)
      << r.out;
  const nlohmann::json result = Result("o");
  EXPECT_EQ(result["dropped_frames"], nlohmann::json({30, 31, 50}));
  EXPECT_EQ(
      result["warnings"][0].get<std::string>().rfind(no_person_warning, 0), 0u);
  const double e3d = result["metrics"]["e3d"].get<double>();
  std::cout << "pickup as keypoints, K = 12: camera-frame e3D " << e3d
            << ", reprojection RMS " << result["reprojection_rms"] << " px\n";
  EXPECT_EQ(result["metrics"]["e3d_frame"], "camera");
  if (testing_util::kSanitizedBuild) return;
  // Measured 0.02707 (this test's output line "pickup as keypoints"); the
  // bound about 13 % above.
  EXPECT_LT(e3d, 0.0305);
  // About the noise (0.5 px per coordinate, 0.71 px per point) and what the
  // default pipeline's temporal prior leaves of noise-free pixels (0.55 px,
  // measured): 0.92 px (the first 60 frames: 0.90 px).
  EXPECT_LT(result["reprojection_rms"].get<double>(), 1.0);

  r =
      Run("reconstruct --input openpose --K 12 --min_confidence 0.1 --output p "
          "--quiet "
          "--max_iterations 3");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find(no_person_warning +
                       "files frame_30_keypoints.json, "
                       "frame_31_keypoints.json, frame_50_keypoints.json)"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(Result("p")["dropped_frames"], nlohmann::json({30, 31, 50}));
}

// A random-basis sequence (K = 3, F = 100, P = 40) as 400-pixel keypoints
// whose scores s are uniform in [0.05, 1], with noise of standard deviation
// 1 px / s (what a score means: a low score, a poor localisation);
// --min_confidence 0.1 drops the ~5 % below 0.1. Weighting each residual
// by its score brings the result closer to the truth than the unweighted
// run (measured on 8 noise seeds with the Python module: e3D 0.0101-0.0112
// against 0.0165-0.0191); equal scores give the unweighted result.
TEST_F(KeypointTest, ConfidenceWeightsBeatUnweightedWhenLowScoresAreNoisy) {
  RandomBasisOptions options;
  options.num_frames = 100;
  options.num_points = 40;
  options.num_bases = 3;
  options.seed = 5;
  SyntheticSequence sequence;
  ASSERT_TRUE(GenerateRandomBasis(options, &sequence).ok());
  std::vector<Eigen::Matrix3Xd> camera;
  for (int t = 0; t < options.num_frames; ++t)
    camera.push_back(sequence.truth.ShapeInCamera(t, 0));
  const PixelSequence s = ToPixels(camera, 400.0);
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.05, 1.0);
  Eigen::ArrayXXd score(options.num_frames, options.num_points);
  Eigen::MatrixXd w = s.w;
  for (int t = 0; t < options.num_frames; ++t) {
    for (int p = 0; p < options.num_points; ++p) {
      score(t, p) = uniform(rng);
      w(2 * t, p) += normal(rng) / score(t, p);
      w(2 * t + 1, p) += normal(rng) / score(t, p);
    }
  }
  WriteCoco(Path("k.json"), w, score, {});
  WriteTruth(Path("truth.mat"), s.truth);
  const std::string common =
      " --input k.json --K 3 --min_confidence 0.1 --truth truth.mat --quiet";
  RunResult r = Run("reconstruct --output plain" + common);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  r = Run("reconstruct --output weighted --confidence_weights" + common);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const double plain = Result("plain")["metrics"]["e3d"].get<double>();
  const double weighted = Result("weighted")["metrics"]["e3d"].get<double>();
  std::cout << "noisy low scores: e3D unweighted " << plain << ", weighted "
            << weighted << "\n";
  EXPECT_LT(plain, 0.03);
  EXPECT_LT(weighted, 0.8 * plain);
  EXPECT_EQ(Result("weighted")["options"]["confidence_weights"], "true");

  // Equal scores: the weights are all 1 after scaling, the same result.
  WriteCoco(Path("equal.json"), w,
            Eigen::ArrayXXd::Constant(score.rows(), score.cols(), 0.5), {});
  r =
      Run("reconstruct --input equal.json --K 3 --output equal "
          "--confidence_weights --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  r = Run("reconstruct --input equal.json --K 3 --output equal_plain --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_LT(MaxDifference(Points("equal"), Points("equal_plain")), 1e-9);
}

TEST_F(KeypointTest, BadFilesAndFlagsGetOneErrorLine) {
  std::ofstream(Path("annotations.json"))
      << R"({"annotations": [], "images": []})";
  ExpectError("reconstruct --input annotations.json --K 2 --output o",
              "annotations.json: expected a list of COCO keypoint results");
  std::ofstream(Path("nokeypoints.json")) << R"([{"image_id": 3, "score": 1}])";
  ExpectError("reconstruct --input nokeypoints.json --K 2 --output o",
              "nokeypoints.json: entry 0 (image_id 3) has no 'keypoints'");
  std::ofstream(Path("text.json")) << "image_id,x,y";
  ExpectError("reconstruct --input text.json --K 2 --output o",
              "text.json: not valid JSON");
  ExpectError(
      "reconstruct --input nokeypoints.json --K 2 --output o --part feet",
      "--part: keypoint part: unknown value \"feet\" (expected one of pose, "
      "face, "
      "hand_left, hand_right)");
  ExpectError(
      "reconstruct --input nokeypoints.json --K 2 --output o --min_confidence "
      "-1",
      "--min_confidence: keypoint options: min_confidence must be finite and "
      ">= 0");
  ExpectError(
      "reconstruct --input nokeypoints.json --K 2 --output o --frame_key=",
      "--frame_key: keypoint options: frame_key must name a field");
  fs::create_directory(Path("empty"));
  ExpectError("reconstruct --input empty --K 2 --output o",
              "empty: no .json files in the folder");

  // Scores that cannot weight: a .mat holds none; a frame with no person
  // would be left out, which a weighted run cannot do yet.
  ASSERT_EQ(
      Run("synth --dataset superquadric --frames 30 --points 20 --output s.mat")
          .exit_code,
      0);
  ExpectError("reconstruct --input s.mat --K 2 --output o --confidence_weights",
              "--confidence_weights: s.mat holds no detector scores");
  SyntheticSequence sequence;
  SuperquadricOptions options;
  options.num_frames = 30;
  options.num_points = 20;
  ASSERT_TRUE(GenerateSuperquadric(options, &sequence).ok());
  WriteCoco(Path("gap.json"), sequence.measurements.W,
            Eigen::ArrayXXd::Constant(30, 20, 0.9), {7});
  ExpectError(
      "reconstruct --input gap.json --K 2 --output o --confidence_weights",
      "gap.json: observation weights (--confidence_weights) with K = 2: the "
      "reconstruction would leave points or frames out, which a weighted run "
      "cannot "
      "do yet (left out of the reconstruction");
  EXPECT_FALSE(fs::exists(Path("o")));
  // Unweighted, the frame is left out and the rest reconstructed.
  const RunResult r =
      Run("reconstruct --input gap.json --K 2 --output o --quiet");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(Result("o")["dropped_frames"], nlohmann::json({7}));
}

// nrsfm view of a keypoint reconstruction: the page's tracks are the file's
// pixels (v down, the page's default orientation: upright), it notes the
// frames with no person, and the frame the reconstruction left out is not
// scored (noise-free random-basis data with the generating K = 2).
TEST_F(KeypointTest, ViewShowsTheKeypointsAsGiven) {
  SyntheticSequence sequence;
  RandomBasisOptions options;
  options.num_frames = 40;
  options.num_points = 20;
  options.num_bases = 2;
  options.seed = 3;
  ASSERT_TRUE(GenerateRandomBasis(options, &sequence).ok());
  std::vector<Eigen::Matrix3Xd> camera;
  for (int t = 0; t < 40; ++t)
    camera.push_back(sequence.truth.ShapeInCamera(t, 0));
  const PixelSequence s = ToPixels(camera, 300.0);
  Eigen::ArrayXXd score = Eigen::ArrayXXd::Constant(40, 20, 0.9);
  score(4, 6) = 0.01;
  WriteCoco(Path("k.json"), s.w, score, {12});
  WriteTruth(Path("truth.mat"), s.truth);
  ASSERT_EQ(
      Run("reconstruct --input k.json --K 2 --output o --quiet").exit_code, 0);
  ASSERT_EQ(Result("o")["dropped_frames"], nlohmann::json({12}));
  const RunResult r =
      Run("view --result o --input k.json --truth truth.mat --output v.html");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("note: k.json: 1 of 40 frames have no person, their "
                       "points are missing "
                       "(image_id 13)"),
            std::string::npos)
      << r.out;
  const std::string html = testing_util::ReadFileToString(Path("v.html"));
  const std::string open =
      "<script id=\"nrsfm-data\" type=\"application/json\">";
  const std::size_t start = html.find(open) + open.size();
  const nlohmann::json data = nlohmann::json::parse(
      html.substr(start, html.find("</script>", start) - start));
  const nlohmann::json& tracks = data["tracks"];
  ASSERT_EQ(tracks.size(), 2u * 40 * 20);
  // Frame 3, point 5: u, v in pixels as in the file (the page keeps 7
  // digits).
  EXPECT_NEAR(tracks[2 * (3 * 20 + 5)].get<double>(), s.w(6, 5), 1e-4);
  EXPECT_NEAR(tracks[2 * (3 * 20 + 5) + 1].get<double>(), s.w(7, 5), 1e-4);
  EXPECT_TRUE(tracks[2 * (4 * 20 + 6)].is_null());   // below min_confidence
  EXPECT_TRUE(tracks[2 * (12 * 20 + 0)].is_null());  // no person
  // The left-out frame is not scored: no error, no reprojection; the others
  // are (noise-free data with the generating K: small errors).
  EXPECT_TRUE(data["frame_error"][12].is_null());
  EXPECT_TRUE(data["reprojection"][2 * (12 * 20)].is_null());
  EXPECT_LT(data["frame_error"][11].get<double>(), 1e-3);
  EXPECT_LT(data["meta"]["metrics"]["e3d"].get<double>(), 1e-3);
}

}  // namespace
}  // namespace nrsfm
