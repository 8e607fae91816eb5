// The rows of the bad-input table (docs/reliability.md) that
// tests/tools/cli_test.cc does not already cover, driven through the real
// `nrsfm` binary: every bad input gives a non-zero exit, one error line naming
// what is wrong, no crash (no "Check failed", no sanitizer report) and no
// output directory; numerical trouble in a solve is reported, never written as
// a trustworthy result.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>

#include "core/io/mat_io.h"
#include "tests/mat_v5_bytes.h"
#include "tests/test_util.h"
#include "tests/tools/tool_test.h"

namespace nrsfm {
namespace {

namespace fs = std::filesystem;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using RunResult = testing_util::CommandResult;

std::string ReadFile(const fs::path& path) {
  return testing_util::ReadFileToString(path.string());
}

// W (2F × P) of a rigid object turning about the vertical axis, with
// orthographic cameras: frame t sees rows x and z of R_y(0.1 t) S.
Eigen::MatrixXd RotatingW(int frames, int points) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::Matrix3Xd shape(3, points);
  for (int p = 0; p < points; ++p) {
    for (int i = 0; i < 3; ++i) shape(i, p) = uniform(rng);
  }
  Eigen::MatrixXd w(2 * frames, points);
  for (int t = 0; t < frames; ++t) {
    const double a = 0.1 * t;
    w.row(2 * t) = std::cos(a) * shape.row(0) + std::sin(a) * shape.row(2);
    w.row(2 * t + 1) =
        shape.row(1) + Eigen::RowVectorXd::Constant(points, 0.5 * a);
  }
  return w;
}

class BadInputTest : public ToolTest {
 protected:
  BadInputTest() : ToolTest("nrsfm_bad_input") {}

  void WriteW(const std::string& name, const Eigen::MatrixXd& w) {
    ASSERT_TRUE(WriteMat(Path(name), MatVersion::kV5, {{"W", w, {}}}).ok());
  }

  // `reconstruct --input <input> <flags> --output o` fails with exit code 1,
  // exactly one line on stderr holding every needle (text of the message
  // itself), no crash report and no o/.
  void ExpectRejected(const std::string& input, const std::string& flags,
                      const std::vector<std::string>& needles) {
    const RunResult r = Run("reconstruct --input " + input + " " + flags +
                            " --output o --quiet");
    EXPECT_EQ(r.exit_code, 1) << input << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << input << "\n"
                                                               << r.err;
    for (const std::string& needle : needles) {
      EXPECT_NE(r.err.find(needle), std::string::npos)
          << input << ": expected '" << needle << "' in\n"
          << r.err;
    }
    for (const char* crash :
         {"Check failed", "Sanitizer", "runtime error", "terminate"}) {
      EXPECT_EQ(r.err.find(crash), std::string::npos) << input << "\n" << r.err;
    }
    EXPECT_FALSE(fs::exists(Path("o"))) << input;
  }
};

TEST_F(BadInputTest, NanAndInfInTheMeasurements) {
  Eigen::MatrixXd w = RotatingW(10, 8);
  w(2, 3) = kNaN;  // u of frame 1, point 3 missing but v present.
  WriteW("half_nan.mat", w);
  ExpectRejected("half_nan.mat", "--K 1",
                 {"half_nan.mat: W: only one coordinate of the observation at "
                  "rows 3-4, column 4 "
                  "(1-based) is NaN; mark a missing point with NaN in both"});

  w = RotatingW(10, 8);
  w(5, 2) = std::numeric_limits<double>::infinity();
  WriteW("inf.mat", w);
  ExpectRejected("inf.mat", "--K 1",
                 {"inf.mat: W: infinite value at row 6, column 3 (1-based); "
                  "use NaN to mark a "
                  "missing entry"});

  std::ofstream(Path("half_nan.txt")) << "1 2 3\nNaN 5 6\n1 2 3\n4 5 6\n";
  ExpectRejected("half_nan.txt", "--K 1",
                 {"half_nan.txt: only one coordinate of the observation at "
                  "rows 1-2, column 1 "
                  "(1-based) is NaN"});
}

TEST_F(BadInputTest, EmptyInputs) {
  std::ofstream(Path("empty.txt")).close();
  ExpectRejected("empty.txt", "--K 1", {"empty.txt: no numbers in the file"});
  std::ofstream(Path("comments.csv")) << "# only a comment\n\n";
  ExpectRejected("comments.csv", "--K 1",
                 {"comments.csv: no numbers in the file"});
  std::ofstream(Path("empty.mat")).close();
  ExpectRejected("empty.mat", "--K 1",
                 {"empty.mat: file is empty, not a .mat file"});
  std::ofstream(Path("empty.obs")).close();
  ExpectRejected("empty.obs", "--K 1",
                 {"empty.obs: no observations in the file"});
  WriteW("empty_w.mat", Eigen::MatrixXd(0, 0));
  ExpectRejected("empty_w.mat", "--K 1", {"empty_w.mat: W is empty (0 x 0)"});
}

TEST_F(BadInputTest, WrongShapes) {
  WriteW("odd_rows.mat", RotatingW(10, 8).topRows(19));
  ExpectRejected(
      "odd_rows.mat", "--K 1",
      {"odd_rows.mat: W: 19 rows is not a multiple of 2 (expected rows "
       "u, v per frame)"});
  // 2FM rows must be a multiple of 2M.
  WriteW("cameras.mat", RotatingW(9, 8));
  ExpectRejected(
      "cameras.mat", "--K 1 --cameras 2",
      {"cameras.mat: W: 18 rows is not a multiple of 2 x 2 cameras"});
  // A mask whose size fits neither (2FM) × P nor (FM) × P.
  ASSERT_TRUE(WriteMat(Path("mask.mat"), MatVersion::kV5,
                       {{"W", RotatingW(10, 8), {}},
                        {"mask", Eigen::MatrixXd::Ones(3, 8), {}}})
                  .ok());
  ExpectRejected("mask.mat", "--K 1 --mask_var mask",
                 {"mask.mat: mask mask is 3 x 8; expected 20 x 8 or 10 x 8 (W "
                  "is 20 x 8, M = 1)"});
  // A ragged text matrix.
  std::ofstream(Path("ragged.txt")) << "1 2 3\n4 5\n";
  ExpectRejected("ragged.txt", "--K 1",
                 {"ragged.txt: line 2 has 2 values, expected 3 as on line 1"});
}

TEST_F(BadInputTest, TooFewFramesOrPoints) {
  WriteW("one_frame.mat", RotatingW(1, 8));
  ExpectRejected("one_frame.mat", "--K 1",
                 {"one_frame.mat: both starts failed: factorization: "
                  "start: needs at least 2 "
                  "frames, got F = 1"});
  WriteW("two_points.mat", RotatingW(10, 2));
  ExpectRejected("two_points.mat", "--K 1",
                 {"two_points.mat: start: K = 1 needs 3K + 1 = 4 points "
                  "and 2F >= 4; got P = 2, "
                  "F = 10"});
}

// A point or a frame with no visible entry is not an error: it is left out
// of the solve, named in a warning and NaN in the result (result.json lists
// it).
TEST_F(BadInputTest, AllMissingPointOrFrameIsLeftOutAndNaN) {
  Eigen::MatrixXd w = RotatingW(10, 8);
  w.col(4).setConstant(kNaN);
  w.middleRows(6, 2).setConstant(kNaN);  // frame 3
  WriteW("lost.mat", w);
  const RunResult r =
      Run("reconstruct --input lost.mat --K 1 --output o --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(
      r.out.find(
          "warning: left out of the reconstruction (K = 1 needs every point "
          "seen in at least 2 views and every frame's views to see at least 4 "
          "points), NaN in the result: point 4 (seen in 0 views); frame 3 "
          "(sees "
          "0 points of those kept)"),
      std::string::npos)
      << r.out;
  const nlohmann::json result =
      nlohmann::json::parse(ReadFile(Path("o/result.json")));
  EXPECT_EQ(result["dropped_points"], nlohmann::json::array({4}));
  EXPECT_EQ(result["dropped_frames"], nlohmann::json::array({3}));
  EXPECT_TRUE(result["solution_usable"].get<bool>());
  // Every row of the left-out point and frame is NaN, the others are numbers.
  std::istringstream csv(ReadFile(Path("o/points_camera.csv")));
  std::string line;
  std::getline(csv, line);
  int rows = 0;
  while (std::getline(csv, line)) {
    int frame = -1, camera = -1, point = -1;
    char comma;
    std::istringstream fields(line);
    fields >> frame >> comma >> camera >> comma >> point;
    EXPECT_EQ(line.find("nan") != std::string::npos, frame == 3 || point == 4)
        << line;
    ++rows;
  }
  EXPECT_EQ(rows, 10 * 8);
}

TEST_F(BadInputTest, NoRotation) {
  // The same 2-D shape in every frame: rank 2 tracks, no 3-D information.
  const Eigen::MatrixXd first = RotatingW(1, 12);
  WriteW("still.mat", first.replicate(15, 1));
  ExpectRejected("still.mat", "--K 1",
                 {"still.mat: both starts failed: factorization: start: "
                  "factorisation start: the "
                  "centred 2D tracks have rank < 3",
                  "the sequence shows no rotation (or the object is flat), so "
                  "depth is unobservable"});
}

TEST_F(BadInputTest, KTooLarge) {
  WriteW("small.mat", RotatingW(10, 8));
  // 3K + 1 = 10 > P = 8.
  ExpectRejected("small.mat", "--K 3",
                 {"small.mat: start: K = 3 needs 3K + 1 = 10 points and "
                  "2F >= 10; got P = 8, "
                  "F = 10"});
  // 3K + 1 beyond the range of an int: counted in 64 bits, not wrapped.
  ExpectRejected(
      "small.mat", "--K 1000000000",
      {"small.mat", "K = 1000000000 needs 3K + 1 = 3000000001 points"});
}

TEST_F(BadInputTest, CorruptFiles) {
  std::mt19937 rng(3);
  std::string noise(4096, '\0');
  for (char& c : noise) c = static_cast<char>(rng());
  std::ofstream(Path("noise.mat"), std::ios::binary) << noise;
  ExpectRejected("noise.mat", "--K 1",
                 {"noise.mat: not a MATLAB .mat file (v4, v5 or v7.3)"});
  // A v5 header followed by garbage.
  WriteW("good.mat", RotatingW(10, 8));
  std::string bytes = ReadFile(Path("good.mat"));
  for (std::size_t i = 140; i < bytes.size(); i += 7)
    bytes[i] = static_cast<char>(rng());
  std::ofstream(Path("garbled.mat"), std::ios::binary) << bytes;
  ExpectRejected("garbled.mat", "--K 1",
                 {"garbled.mat: the .mat file is truncated or corrupt "
                  "(variable 1 at byte 128 "
                  "(compressed): its compressed data cannot be inflated"});
  // A truncated v7.3 (HDF5) file.
  ASSERT_TRUE(
      WriteMat(Path("v73.mat"), MatVersion::kV73, {{"W", RotatingW(10, 8), {}}})
          .ok());
  bytes = ReadFile(Path("v73.mat"));
  std::ofstream(Path("cut73.mat"), std::ios::binary)
      << bytes.substr(0, bytes.size() / 2);
  ExpectRejected("cut73.mat", "--K 1",
                 {"cut73.mat: the .mat file is truncated or corrupt ("});
}

// A v5 file whose W is an empty 3-D array (4 x 3 x 0: no slice at all) made
// `reconstruct` index the first of no slices and die with SIGSEGV. The file
// is written from the bytes of tests/mat_v5_bytes.h; the same W compressed
// (v5) and in HDF5 (v7.3) comes from WriteMat.
TEST_F(BadInputTest, EmptyThreeDimensionalWIsAnErrorNotACrash) {
  namespace v5 = testing_util::v5;
  const std::string bytes = v5::Header() + v5::Double("W", {4, 3, 0}, {});
  std::ofstream(Path("crash.mat"), std::ios::binary)
      .write(bytes.data(), bytes.size());
  const RunResult r = Run("reconstruct --input crash.mat --K 1 --output out");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.err,
            "nrsfm reconstruct: error: crash.mat: W is empty (4 x 3 x 0)\n");
  EXPECT_FALSE(fs::exists(Path("out")));

  for (MatVersion version : {MatVersion::kV5, MatVersion::kV73}) {
    const std::string name =
        version == MatVersion::kV5 ? "zlib.mat" : "hdf5.mat";
    ASSERT_TRUE(
        WriteMat(Path(name), version, {{"W", Eigen::MatrixXd(0, 0), {4, 3, 0}}})
            .ok());
    ExpectRejected(name, "--K 1", {name + ": W is empty (4 x 3 x 0)"});
  }
}

// The siblings of that crash: every zero-sized dimension of W, X and P3_gt,
// an empty mask, an empty cell or a struct with an empty field, as input and
// as the truth of `reconstruct --truth` and `evaluate`.
TEST_F(BadInputTest, EmptyVariablesOfEveryKindAreOneLineErrors) {
  namespace v5 = testing_util::v5;
  const auto write = [&](const std::string& name,
                         const std::string& variables) {
    const std::string bytes = v5::Header() + variables;
    std::ofstream(Path(name), std::ios::binary)
        .write(bytes.data(), bytes.size());
  };
  write("w_0xp.mat", v5::Double("W", {0, 8}, {}));
  ExpectRejected("w_0xp.mat", "--K 1", {"w_0xp.mat: W is empty (0 x 8)"});
  write("w_2fx0.mat", v5::Double("W", {20, 0}, {}));
  ExpectRejected("w_2fx0.mat", "--K 1", {"w_2fx0.mat: W is empty (20 x 0)"});
  write("x_3xpx0.mat", v5::Double("X", {3, 8, 0}, {}));
  ExpectRejected("x_3xpx0.mat", "--K 1",
                 {"x_3xpx0.mat: X is empty (3 x 8 x 0)"});
  write("x_3x0xf.mat", v5::Double("X", {3, 0, 10}, {}));
  ExpectRejected("x_3x0xf.mat", "--K 1",
                 {"x_3x0xf.mat: X is empty (3 x 0 x 10)"});
  write("p3_0xp.mat", v5::Double("P3_gt", {0, 8}, {}));
  ExpectRejected("p3_0xp.mat", "--K 1", {"p3_0xp.mat: P3_gt is empty (0 x 8)"});
  write("cell.mat", v5::Cell("W", {1, 1}, {v5::EmptyMatrix()}));
  ExpectRejected(
      "cell.mat", "--K 1",
      {"cell.mat: variable 'W' is a cell array, not a numeric array"});
  write("struct.mat", v5::Struct("W", {"empty"}, {v5::EmptyMatrix()}));
  ExpectRejected("struct.mat", "--K 1",
                 {"struct.mat: variable 'W' is a struct, not a numeric array"});
  const Eigen::MatrixXd w = RotatingW(10, 8);
  write("mask.mat",
        v5::Double("W", {20, 8},
                   std::vector<double>(w.data(), w.data() + w.size())) +
            v5::Double("mask", {0, 0}, {}));
  ExpectRejected("mask.mat", "--K 1 --mask_var mask",
                 {"mask.mat: mask mask is 0 x 0; expected 20 x 8 or 10 x 8"});

  // Empty truth: X with no frame, S with no rows.
  write("truth_x.mat", v5::Double("X", {3, 8, 0}, {}));
  write("truth_s.mat",
        v5::Double("S", {0, 8}, {}) +
            v5::Double("Rs", {20, 3}, std::vector<double>(60, 0.0)));
  WriteW("w.mat", w);
  ExpectRejected(
      "w.mat", "--K 1 --truth truth_x.mat",
      {"truth_x.mat: X is empty (3 x 8 x 0); expected a 3 x P x F array"});
  ExpectRejected("w.mat", "--K 1 --truth truth_s.mat",
                 {"truth_s.mat: S is empty (0 x 8)"});
  const RunResult good =
      Run("reconstruct --input w.mat --K 1 --output o --quiet");
  ASSERT_EQ(good.exit_code, 0) << good.err;
  const RunResult evaluated = Run("evaluate --truth truth_x.mat --result o");
  EXPECT_EQ(evaluated.exit_code, 1) << evaluated.err;
  EXPECT_EQ(evaluated.err,
            "nrsfm evaluate: error: truth_x.mat: X is empty (3 x 8 x 0); "
            "expected a 3 x P x F "
            "array\n");
}

// Hostile input costs what its size justifies. Two inputs that took
// gigabytes before the readers bounded what a file may claim (release CLI,
// /usr/bin/time; docs/reliability.md): a 400-byte corrupt v5 file of the
// fuzz corpus whose name tag claims 4 GB (10.5 s, 4.1 GB peak: matio
// allocated and filled it) and two lines of an observation list with frame
// index 1 300 000 (6.3 s, 2.0 GB: a W of 1 300 001 frames). In a process
// limited to 512 MB of address space each ends with its one-line error.
TEST_F(BadInputTest, HostileInputsEndWithTheirErrorInHalfAGigabyte) {
  if (testing_util::kSanitizedBuild) {
    GTEST_SKIP()
        << "the sanitizers reserve far more than 512 MB of address space";
  }
  const std::string corrupt = testing_util::ReadFileToString(
      NRSFM_FUZZ_CORPUS_DIR "/mat/c9c8a659ddc61226d6874fc3689b92405eb6f95f");
  ASSERT_EQ(corrupt.size(), 400u);
  std::ofstream(Path("corrupt.mat"), std::ios::binary) << corrupt;
  std::ofstream(Path("two.obs")) << "0 0 0 1 2\n1300000 0 99 1.0 2.0\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"corrupt.mat",
       "nrsfm reconstruct: error: corrupt.mat: the .mat file is truncated or "
       "corrupt "
       "(variable 1 at byte 128: a data element claims 4227858433 bytes, more "
       "than the 16 left "
       "in its array)\n"},
      {"two.obs",
       "nrsfm reconstruct: error: two.obs: both starts failed: factorization: "
       "start: K = 1 "
       "needs 3K + 1 = 4 points and 2F >= 4; got P = 2, F = 2; rigid: "
       "start: K = 1 needs "
       "3K + 1 = 4 points and 2F >= 4; got P = 2, F = 2 (F and P count the "
       "frames and points "
       "the list mentions; its largest indices are frame 1300000, point 99)\n"},
  };
  for (const auto& [input, error] : cases) {
    const RunResult r = testing_util::RunInDirectory(
        dir_, "/bin/sh",
        std::string("-c 'ulimit -v 524288 && exec ") + NRSFM_CLI +
            " reconstruct --input " + input + " --K 1 --output o --quiet'");
    EXPECT_EQ(r.exit_code, 1) << input << "\n" << r.err;
    EXPECT_EQ(r.err, error);
    EXPECT_FALSE(fs::exists(Path("o")));
  }
}

// A list that reconstructs, plus one stray line with frame index 2 000 000:
// over the index that would be a W of 272 MB for a 1.6 kB file, so the
// result holds the 11 frames the list mentions (the stray one left out for
// seeing one point), says so, and result.json maps them to the list's
// indices.
TEST_F(BadInputTest, StrayFrameIndexIsOneMoreFrameNotAHugeW) {
  const Eigen::MatrixXd w = RotatingW(10, 8);
  std::ofstream list(Path("stray.obs"));
  list.precision(17);
  for (int t = 0; t < 10; ++t) {
    for (int p = 0; p < 8; ++p)
      list << t << " 0 " << p << " " << w(2 * t, p) << " " << w(2 * t + 1, p)
           << "\n";
  }
  list << "2000000 0 3 0.5 0.5\n";
  list.close();
  const RunResult r =
      Run("reconstruct --input stray.obs --K 1 --output o --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("input: stray.obs  F = 11, M = 1, P = 8"),
            std::string::npos)
      << r.out;
  EXPECT_NE(
      r.out.find(
          "warning: the list's largest indices (frame 2000000, point 7) would "
          "make too large a W for it: the result holds only the 11 frames and "
          "8 "
          "points it mentions, numbered 0..10 and 0..7 in increasing order of "
          "their index (result.json: input_frames and input_points give each "
          "one's index in the list)"),
      std::string::npos)
      << r.out;
  const nlohmann::json result =
      nlohmann::json::parse(ReadFile(Path("o/result.json")));
  EXPECT_EQ(result["input_frames"].get<std::vector<int>>(),
            (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 2000000}));
  EXPECT_EQ(result["input_points"].get<std::vector<int>>(),
            (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(result["dropped_frames"], nlohmann::json::array({10}));
  EXPECT_EQ(result["num_frames"], 11);
  const std::string csv = ReadFile(Path("o/points_camera.csv"));
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 11 * 8);
}

TEST_F(BadInputTest, WrongVariableOrFormat) {
  ASSERT_TRUE(
      WriteMat(Path("vars.mat"), MatVersion::kV5,
               {{"A", RotatingW(10, 8), {}}, {"B", RotatingW(4, 8), {}}})
          .ok());
  // Auto-detection finds none of W, P3_gt, X and lists what there is.
  ExpectRejected("vars.mat", "--K 1",
                 {"vars.mat: none of the variables W, P3_gt, X is in the file "
                  "(it has: A, B); name one"});
  ExpectRejected("vars.mat", "--K 1 --var Z",
                 {"vars.mat: no variable 'Z'; the file has: A, B"});
  WriteW("w.unknown", RotatingW(10, 8));
  ExpectRejected("w.unknown", "--K 1",
                 {"w.unknown: cannot tell the input format from the extension "
                  "'.unknown'"});
}

TEST_F(BadInputTest, UnreadableInputPath) {
  fs::create_directory(Path("adir.mat"));
  ExpectRejected("adir.mat", "--K 1",
                 {"adir.mat: is a directory, not a .mat file"});
  ExpectRejected("missing.txt", "--K 1", {"missing.txt: no such file"});
}

TEST_F(BadInputTest, UnwritableOutput) {
  WriteW("w.mat", RotatingW(10, 8));
  // The output names an existing file.
  std::ofstream(Path("file")) << "x";
  const RunResult r =
      Run("reconstruct --input w.mat --K 1 --output file --quiet");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.err,
            "nrsfm reconstruct: error: output 'file' exists and is not an "
            "empty directory "
            "(use --overwrite to replace an earlier result)\n");
  EXPECT_EQ(ReadFile(Path("file")), "x");
  // The output lies under a file.
  const RunResult under =
      Run("reconstruct --input w.mat --K 1 --output file/sub --quiet");
  EXPECT_EQ(under.exit_code, 1) << under.err;
  EXPECT_NE(under.err.find("file: cannot create the directory"),
            std::string::npos)
      << under.err;
}

TEST_F(BadInputTest, OverflowingValuesAreNotHidden) {
  // Values near the top of the double range: squares overflow to Inf. The
  // tool must either reject the data or report an unusable solution; it must
  // never write a result that claims to be usable.
  WriteW("huge.mat", RotatingW(10, 8) * 1e300);
  const RunResult r =
      Run("reconstruct --input huge.mat --K 1 --output o --quiet");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_EQ(r.err.find("Check failed"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("runtime error"), std::string::npos) << r.err;
  if (fs::exists(Path("o/result.json"))) {
    const nlohmann::json json =
        nlohmann::json::parse(ReadFile(Path("o/result.json")));
    EXPECT_FALSE(json["solution_usable"].get<bool>());
    EXPECT_FALSE(json["warnings"].empty());
  } else {
    EXPECT_NE(r.err.find("huge.mat"), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace nrsfm
