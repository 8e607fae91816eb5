// Detector keypoints (core/io/keypoint_io.h): COCO keypoint results and
// OpenPose folders written here by hand, read into W, visibility and
// confidence; frame order, frames with no person or several, and the
// one-line errors of files of another schema.
#include "core/io/keypoint_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/io/read_measurements.h"
#include "tests/test_util.h"

namespace nrsfm {
namespace {

namespace fs = std::filesystem;

void WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The message of reading `path` as COCO results ("OK" on success).
std::string ReadCoco(const std::string& path, const KeypointOptions& options,
                     Keypoints* k) {
  const Status status = ReadCocoKeypoints(path, options, k);
  return status.ok() ? "OK" : status.message();
}

std::string ReadOpenPose(const std::string& path,
                         const KeypointOptions& options, Keypoints* k) {
  const Status status = ReadOpenPoseFolder(path, options, k);
  return status.ok() ? "OK" : status.message();
}

class KeypointIo : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing_util::MakeTempDir("nrsfm_keypoints"); }
  std::string Path(const std::string& name) const {
    return (fs::path(dir_) / name).string();
  }
  std::string dir_;
};

TEST(NaturalLess, NumbersInNamesCompareAsNumbers) {
  EXPECT_TRUE(NaturalLess("f2", "f10"));
  EXPECT_FALSE(NaturalLess("f10", "f2"));
  EXPECT_TRUE(NaturalLess("a_000000000009_keypoints.json",
                          "a_000000000010_keypoints.json"));
  EXPECT_TRUE(NaturalLess("frame9.json", "frame10.json"));
  EXPECT_TRUE(NaturalLess("a", "b"));
  EXPECT_TRUE(NaturalLess("a", "a1"));
  EXPECT_FALSE(NaturalLess("a", "a"));
  // The same number: more leading zeros first, so the order is total.
  EXPECT_TRUE(NaturalLess("x007", "x7"));
  EXPECT_FALSE(NaturalLess("x7", "x007"));
  EXPECT_TRUE(NaturalLess("7", "8"));
}

// Three entries, two keypoints each; image_id 5 has no entry (a frame with
// no person); image_id 6 has two entries (the higher score is used); one
// keypoint below the threshold and one of score 0 are missing.
TEST_F(KeypointIo, CocoResultsIntoWAndConfidence) {
  WriteText(Path("k.json"), R"([
    {"image_id": 6, "category_id": 1, "keypoints": [1, 2, 0.5, 3, 4, 0.6], "score": 0.4},
    {"image_id": 4, "category_id": 1, "keypoints": [10.5, 20.25, 0.9, 30, 40, 0.02], "score": 0.9},
    {"image_id": 6, "category_id": 1, "keypoints": [100, 200, 0.7, 300, 400, 0], "score": 0.8},
    {"image_id": 7, "category_id": 1, "keypoints": [7, 8, 1, 9, 10, 1], "score": 1}
  ])");
  Keypoints k;
  ASSERT_EQ(ReadCoco(Path("k.json"), KeypointOptions(), &k), "OK");
  const Measurements& m = k.measurements;
  // Frames are image_id 4, 5, 6, 7.
  ASSERT_EQ(m.num_frames, 4);
  ASSERT_EQ(m.num_points, 2);
  EXPECT_EQ(m.num_cameras, 1);
  ASSERT_TRUE(m.Validate().ok());
  // Frame 0 (image_id 4): point 0 visible in pixels as given, point 1 below
  // min_confidence = 0.05.
  EXPECT_EQ(m.W(0, 0), 10.5);
  EXPECT_EQ(m.W(1, 0), 20.25);
  EXPECT_TRUE(m.visible(0, 0));
  EXPECT_FALSE(m.visible(0, 1));
  EXPECT_TRUE(std::isnan(m.W(0, 1)));
  EXPECT_EQ(k.confidence(0, 0), 0.9);
  EXPECT_EQ(k.confidence(0, 1), 0.02);  // the score is kept, the point missing
  // Frame 1 (image_id 5): no entry.
  EXPECT_FALSE(m.visible.row(1).any());
  EXPECT_TRUE(k.confidence.row(1).isNaN().all());
  // Frame 2 (image_id 6): the entry of score 0.8; its point 1 has score 0.
  EXPECT_EQ(m.W(4, 0), 100.0);
  EXPECT_EQ(m.W(5, 0), 200.0);
  EXPECT_FALSE(m.visible(2, 1));
  EXPECT_EQ(k.confidence(2, 0), 0.7);
  EXPECT_EQ(k.confidence(2, 1), 0.0);
  // Frame 3.
  EXPECT_EQ(m.W(6, 1), 9.0);
  EXPECT_EQ(m.W(7, 1), 10.0);
  ASSERT_EQ(k.warnings.size(), 2u);
  EXPECT_EQ(
      k.warnings[0],
      "1 of 4 frames have no person, their points are missing (image_id 5)");
  EXPECT_EQ(k.warnings[1],
            "1 of 4 frames have several entries (image_id 6): the one with the "
            "highest "
            "'score' is used");

  // A higher threshold hides frame 0's point 0 too (0.9 < 0.95) and frame
  // 3's (score 1) stay.
  KeypointOptions strict;
  strict.min_confidence = 0.95;
  ASSERT_EQ(ReadCoco(Path("k.json"), strict, &k), "OK");
  EXPECT_EQ(k.measurements.NumVisible(), 2);
  EXPECT_TRUE(k.measurements.visible(3, 0) && k.measurements.visible(3, 1));
  strict.min_confidence = 2.0;
  EXPECT_EQ(ReadCoco(Path("k.json"), strict, &k),
            Path("k.json") +
                ": no keypoint has a score of at least min_confidence = 2 (the "
                "highest is 1)");
}

// --frame_key: strings in natural order, other numbers as they sort; one
// frame per distinct value, no gaps.
TEST_F(KeypointIo, CocoFramesByAnotherKey) {
  WriteText(Path("s.json"), R"([
    {"image_id": 1, "file": "frame10.jpg", "keypoints": [10, 0, 1, 0, 0, 1]},
    {"image_id": 2, "file": "frame9.jpg", "keypoints": [9, 0, 1, 0, 0, 1]},
    {"image_id": 3, "file": "frame100.jpg", "keypoints": [100, 0, 1, 0, 0, 1]}
  ])");
  KeypointOptions options;
  options.frame_key = "file";
  Keypoints k;
  ASSERT_EQ(ReadCoco(Path("s.json"), options, &k), "OK");
  ASSERT_EQ(k.measurements.num_frames, 3);
  EXPECT_EQ(k.measurements.W(0, 0), 9.0);
  EXPECT_EQ(k.measurements.W(2, 0), 10.0);
  EXPECT_EQ(k.measurements.W(4, 0), 100.0);
  EXPECT_TRUE(k.warnings.empty());

  WriteText(Path("t.json"), R"([
    {"time": 0.5, "keypoints": [5, 0, 1, 0, 0, 1]},
    {"time": 0.25, "keypoints": [2.5, 0, 1, 0, 0, 1]},
    {"time": 2, "keypoints": [20, 0, 1, 0, 0, 1]}
  ])");
  options.frame_key = "time";
  ASSERT_EQ(ReadCoco(Path("t.json"), options, &k), "OK");
  ASSERT_EQ(k.measurements.num_frames, 3);
  EXPECT_EQ(k.measurements.W(0, 0), 2.5);
  EXPECT_EQ(k.measurements.W(2, 0), 5.0);
  EXPECT_EQ(k.measurements.W(4, 0), 20.0);
}

TEST_F(KeypointIo, CocoSchemaErrorsAreOneLineNamingTheEntryAndField) {
  struct Case {
    std::string json, expected;
  };
  const std::string p = Path("bad.json");
  const std::vector<Case> cases = {
      {"[1, 2", "not valid JSON (parse error at line 1, column 6"},
      {"{\"annotations\": [], \"images\": []}",
       "got a object; this looks like a COCO annotation file"},
      {"{\"version\": 1.3, \"people\": []}",
       "this looks like one OpenPose frame"},
      {"[]", "the list of keypoint results is empty"},
      {"[3]", "entry 0 is a number, not an object"},
      {"[{\"keypoints\": [1, 2, 1]}]",
       "entry 0 has no 'image_id' (the frame key; --frame_key names another "
       "field)"},
      {"[{\"image_id\": [1], \"keypoints\": [1, 2, 1]}]",
       "entry 0: 'image_id' is a array, not a number or a string"},
      {"[{\"image_id\": 1}]", "entry 0 (image_id 1) has no 'keypoints'"},
      {"[{\"image_id\": 1, \"keypoints\": [1, 2]}]",
       "entry 0 (image_id 1): 'keypoints' has 2 values, not a multiple of 3"},
      {"[{\"image_id\": 1, \"keypoints\": [1, \"2\", 1]}]",
       "entry 0 (image_id 1): 'keypoints'[1] is a string, not a number"},
      {"[{\"image_id\": 1, \"keypoints\": []}]",
       "entry 0 (image_id 1): 'keypoints' is empty"},
      {"[{\"image_id\": 1, \"keypoints\": [1, 1e999, 1]}]",
       "not valid JSON (number overflow parsing '1e999')"},

      {"[{\"image_id\": 1, \"keypoints\": [1, 2, 1]}, {\"image_id\": 2, "
       "\"keypoints\": [1, 2, 1, "
       "3, 4, 1]}]",
       "entry 1 (image_id 2) has 2 keypoints but entry 0 has 1"},
      {"[{\"image_id\": 1, \"keypoints\": [1, 2, 1], \"score\": \"high\"}]",
       "entry 0 (image_id 1): 'score' is a string, not a number"},
      {"[{\"image_id\": 1, \"keypoints\": [1, 2, 1]}, {\"image_id\": \"b\", "
       "\"keypoints\": [1, 2, "
       "1]}]",
       "entry 1 (image_id \"b\"): 'image_id' is a string but entry 0's is a "
       "number"},
      {"[{\"image_id\": 0, \"keypoints\": [1, 2, 1]}, {\"image_id\": 5000000, "
       "\"keypoints\": [1, "
       "2, 1]}]",
       "'image_id' runs from 0 to 5000000, more than 10^6 frames"},
  };
  for (const Case& c : cases) {
    WriteText(p, c.json);
    Keypoints k;
    const std::string message = ReadCoco(p, KeypointOptions(), &k);
    EXPECT_TRUE(Contains(message, c.expected)) << c.json << "\n" << message;
    EXPECT_EQ(message.rfind(p + ": ", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  // Two entries 10^6 frames apart with 300 keypoints: a W of 6·10^8
  // entries is refused before it is allocated.
  std::string many = "[1, 2, 1";
  for (int i = 1; i < 300; ++i) many += ", 1, 2, 1";
  WriteText(p, "[{\"image_id\": 0, \"keypoints\": " + many +
                   "]}, {\"image_id\": 999999, "
                   "\"keypoints\": " +
                   many + "]}]");
  Keypoints k;
  EXPECT_EQ(ReadCoco(p, KeypointOptions(), &k),
            p + ": F = 1000000 frames of P = 300 keypoints imply a W larger "
                "than 2^28 entries");
  EXPECT_EQ(ReadCoco(Path("nope.json"), KeypointOptions(), &k),
            Path("nope.json") + ": no such file");
  KeypointOptions bad;
  bad.min_confidence = -1;
  EXPECT_TRUE(
      Contains(ReadCoco(p, bad, &k), "min_confidence must be finite and >= 0"));
}

// An OpenPose folder: frames in the natural order of the file names, the
// chosen part of people[0], a frame with no person and one with two.
TEST_F(KeypointIo, OpenPoseFolderIntoWAndConfidence) {
  const std::string folder = Path("op");
  fs::create_directory(folder);
  const auto frame = [&](const std::string& name, const std::string& people) {
    WriteText(folder + "/" + name,
              "{\"version\": 1.3, \"people\": [" + people + "]}");
  };
  const auto person = [](const std::string& pose, const std::string& face) {
    return "{\"person_id\": [-1], \"pose_keypoints_2d\": [" + pose +
           "], \"face_keypoints_2d\": [" + face +
           "], \"hand_left_keypoints_2d\": [], \"hand_right_keypoints_2d\": "
           "[]}";
  };
  frame("v_10_keypoints.json", person("10, 11, 0.9, 12, 13, 0.8", ""));
  frame("v_9_keypoints.json", person("9, 10, 0.9, 0, 0, 0", "1, 1, 1"));
  frame("v_11_keypoints.json", "");
  frame("v_12_keypoints.json", person("12, 13, 0.7, 14, 15, 0.6", "") + ", " +
                                   person("50, 50, 1, 60, 60, 1", ""));
  WriteText(folder + "/notes.txt", "not a frame");
  Keypoints k;
  ASSERT_EQ(ReadOpenPose(folder, KeypointOptions(), &k), "OK");
  const Measurements& m = k.measurements;
  ASSERT_EQ(m.num_frames, 4);
  ASSERT_EQ(m.num_points, 2);
  // v_9, v_10, v_11, v_12.
  EXPECT_EQ(m.W(0, 0), 9.0);
  EXPECT_FALSE(m.visible(0, 1));  // OpenPose's 0, 0, 0: not found
  EXPECT_EQ(m.W(2, 1), 12.0);
  EXPECT_EQ(m.W(3, 1), 13.0);
  EXPECT_FALSE(m.visible.row(2).any());
  EXPECT_EQ(m.W(6, 0), 12.0);  // people[0] of v_12
  EXPECT_EQ(k.confidence(3, 1), 0.6);
  ASSERT_EQ(k.warnings.size(), 2u);
  EXPECT_EQ(k.warnings[0],
            "1 of 4 frames have no person, their points are missing (files "
            "v_11_keypoints.json)");
  EXPECT_EQ(k.warnings[1],
            "1 of 4 frames have more than one person (files "
            "v_12_keypoints.json): people[0] "
            "is used");

  // The face: only v_9 has it; the other frames have no such keypoints.
  KeypointOptions face;
  ASSERT_TRUE(ParseKeypointPart("face", &face.part).ok());
  ASSERT_EQ(ReadOpenPose(folder, face, &k), "OK");
  EXPECT_EQ(k.measurements.num_points, 1);
  EXPECT_EQ(k.measurements.NumVisible(), 1);
  EXPECT_TRUE(Contains(k.warnings[0], "3 of 4 frames have no person"));
  // No hands anywhere.
  KeypointOptions hand;
  ASSERT_TRUE(ParseKeypointPart("hand_left", &hand.part).ok());
  EXPECT_EQ(
      ReadOpenPose(folder, hand, &k),
      folder +
          ": none of the 4 frames has a person with hand_left_keypoints_2d "
          "(OpenPose computes faces and hands with --face, --hand)");
  KeypointPart part;
  EXPECT_TRUE(Contains(ParseKeypointPart("feet", &part).message(), "feet"));
}

TEST_F(KeypointIo, OpenPoseErrorsNameTheFile) {
  const std::string folder = Path("op");
  Keypoints k;
  EXPECT_EQ(ReadOpenPose(folder, KeypointOptions(), &k),
            folder + ": no such folder");
  fs::create_directory(folder);
  EXPECT_TRUE(Contains(ReadOpenPose(folder, KeypointOptions(), &k),
                       folder + ": no .json files in the folder"));
  WriteText(folder + "/a1.json",
            "{\"people\": [{\"pose_keypoints_2d\": [1, 2, 1, 3, 4, 1]}]}");
  WriteText(folder + "/a2.json",
            "{\"people\": [{\"pose_keypoints_2d\": [1, 2, 1]}]}");
  EXPECT_EQ(ReadOpenPose(folder, KeypointOptions(), &k),
            folder +
                "/a2.json: people[0].pose_keypoints_2d has 1 keypoints but "
                "a1.json has 2");
  WriteText(folder + "/a2.json", "{\"people\": [{\"face_keypoints_2d\": []}]}");
  EXPECT_EQ(ReadOpenPose(folder, KeypointOptions(), &k),
            folder + "/a2.json: people[0] has no 'pose_keypoints_2d'");
  WriteText(folder + "/a2.json", "[1, 2, 3]");
  EXPECT_EQ(
      ReadOpenPose(folder, KeypointOptions(), &k),
      folder + "/a2.json: no 'people' list (not an OpenPose keypoint file)");
  WriteText(folder + "/a2.json", "{\"people\": [");
  EXPECT_TRUE(Contains(ReadOpenPose(folder, KeypointOptions(), &k),
                       folder + "/a2.json: not valid JSON"));
  EXPECT_TRUE(Contains(ReadOpenPose(folder + "/a1.json", KeypointOptions(), &k),
                       "is not a folder"));
}

// ReadMeasurements picks the format by the extension (.json: COCO) or a
// folder (OpenPose) and hands the confidences and warnings on.
TEST_F(KeypointIo, ReadMeasurementsReadsBothFormats) {
  WriteText(Path("k.json"), R"([
    {"image_id": 1, "keypoints": [1, 2, 0.5, 3, 4, 0.25]},
    {"image_id": 3, "keypoints": [5, 6, 0.75, 7, 8, 1]}
  ])");
  Measurements m;
  InputDetails details;
  ASSERT_TRUE(
      ReadMeasurements(Path("k.json"), InputOptions(), &m, &details).ok());
  EXPECT_EQ(m.num_frames, 3);
  EXPECT_EQ(details.confidence.rows(), 3);
  EXPECT_EQ(details.confidence(0, 1), 0.25);
  EXPECT_EQ(details.confidence(2, 0), 0.75);
  ASSERT_EQ(details.warnings.size(), 1u);
  EXPECT_TRUE(Contains(details.warnings[0], "1 of 3 frames have no person"));

  fs::create_directory(Path("op"));
  WriteText(Path("op/f0.json"),
            "{\"people\": [{\"pose_keypoints_2d\": [1, 2, 1, 3, 4, 1]}]}");
  WriteText(Path("op/f1.json"),
            "{\"people\": [{\"pose_keypoints_2d\": [5, 6, 1, 7, 8, 0.5]}]}");
  ASSERT_TRUE(ReadMeasurements(Path("op"), InputOptions(), &m, &details).ok());
  EXPECT_EQ(m.num_frames, 2);
  EXPECT_EQ(m.W(3, 1), 8.0);
  EXPECT_EQ(details.confidence(1, 1), 0.5);
  EXPECT_TRUE(details.warnings.empty());

  // Other formats hold no confidences.
  WriteText(Path("w.txt"), "1 2 3 4\n5 6 7 8\n");
  ASSERT_TRUE(
      ReadMeasurements(Path("w.txt"), InputOptions(), &m, &details).ok());
  EXPECT_EQ(details.confidence.size(), 0);

  InputOptions two_cameras;
  two_cameras.num_cameras = 2;
  EXPECT_TRUE(
      Contains(ReadMeasurements(Path("k.json"), two_cameras, &m).message(),
               "keypoint files hold one camera"));
  InputOptions with_variable;
  with_variable.variable = "W";
  EXPECT_TRUE(
      Contains(ReadMeasurements(Path("op"), with_variable, &m).message(),
               "read as openpose"));
  InputFormat format;
  ASSERT_TRUE(ParseInputFormat("coco", &format).ok());
  EXPECT_EQ(format, InputFormat::kCoco);
  ASSERT_TRUE(ParseInputFormat("openpose", &format).ok());
  EXPECT_EQ(format, InputFormat::kOpenPose);
}

}  // namespace
}  // namespace nrsfm
