#include "core/io/read_measurements.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "core/io/mat_io.h"
#include "tests/mat_v5_bytes.h"
#include "tests/test_util.h"

namespace nrsfm {
namespace {

using testing_util::MakeTempDir;

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

Eigen::MatrixXd RandomMatrix(int rows, int cols, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-300.0, 300.0);
  Eigen::MatrixXd m(rows, cols);
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = uniform(rng);
  return m;
}

std::string Read(const std::string& path, const InputOptions& options,
                 Measurements* m) {
  const Status s = ReadMeasurements(path, options, m);
  return s.ok() ? "OK" : s.message();
}

void WriteBytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

TEST(ReadMeasurements, RealDrinkAndFace) {
  NRSFM_SKIP_WITHOUT_SHARED_DATA(dir);
  Measurements m;
  ASSERT_EQ(Read(dir + "/drink.mat", {}, &m), "OK");
  EXPECT_EQ(m.num_frames, 1102);
  EXPECT_EQ(m.num_cameras, 1);
  EXPECT_EQ(m.num_points, 41);
  EXPECT_TRUE(m.IsComplete());

  ASSERT_EQ(Read(dir + "/face.mat", {}, &m), "OK");  // v4, via P3_gt
  EXPECT_EQ(m.num_frames, 316);
  EXPECT_EQ(m.num_points, 40);
  EXPECT_TRUE(m.IsComplete());
  Eigen::MatrixXd p3;
  ASSERT_TRUE(ReadMatVariable(dir + "/face.mat", "P3_gt", &p3).ok());
  for (int p = 0; p < 40; ++p) {
    EXPECT_EQ(m.W(0, p), p3(0, p));                    // x of frame 0
    EXPECT_EQ(m.W(1, p), p3(316, p));                  // y of frame 0
    EXPECT_EQ(m.W(2 * 315 + 1, p), p3(316 + 315, p));  // y of the last frame
  }
  EXPECT_EQ(m.W(0, 0), 196.31549072265625);  // a hand-read value (float-exact)
}

TEST(ReadMeasurements, MaskAndNaNRoundTripInEveryVersion) {
  const std::string dir = MakeTempDir("read_meas_mask");
  const int num_frames = 5, num_points = 6;
  Eigen::MatrixXd w = RandomMatrix(2 * num_frames, num_points, 21);
  w.block(2 * 1, 3, 2, 1)
      .setConstant(std::nan(""));  // frame 1, point 3 missing
  Eigen::MatrixXd mask = Eigen::MatrixXd::Ones(num_frames, num_points);
  mask(2, 0) = 0;  // frame 2, point 0 hidden by the mask
  mask(4, 5) = 7;  // any nonzero value is visible
  Eigen::MatrixXd mask_rows(2 * num_frames, num_points);  // the 2F x P form
  for (int t = 0; t < num_frames; ++t)
    mask_rows.middleRows(2 * t, 2) << mask.row(t), mask.row(t);

  for (MatVersion version :
       {MatVersion::kV4, MatVersion::kV5, MatVersion::kV73}) {
    SCOPED_TRACE(static_cast<int>(version));
    const std::string path =
        dir + "/v" + std::to_string(static_cast<int>(version)) + ".mat";
    ASSERT_TRUE(
        WriteMat(path, version,
                 {{"W", w, {}}, {"vis", mask, {}}, {"vis2", mask_rows, {}}})
            .ok());
    Measurements plain;
    ASSERT_EQ(Read(path, {}, &plain), "OK");
    EXPECT_EQ(plain.NumVisible(), num_frames * num_points - 1);
    for (const char* mask_name : {"vis", "vis2"}) {
      InputOptions options;
      options.mask_variable = mask_name;
      Measurements m;
      ASSERT_EQ(Read(path, options, &m), "OK");
      EXPECT_EQ(m.NumVisible(), num_frames * num_points - 2);
      EXPECT_FALSE(m.visible(1, 3));  // NaN in W
      EXPECT_FALSE(m.visible(2, 0));  // mask
      EXPECT_TRUE(std::isnan(m.W(4, 0)));
      for (int t = 0; t < num_frames; ++t) {
        for (int p = 0; p < num_points; ++p) {
          if (!m.visible(t, p)) continue;
          EXPECT_EQ(m.W(2 * t, p), w(2 * t, p));
          EXPECT_EQ(m.W(2 * t + 1, p), w(2 * t + 1, p));
        }
      }
    }
  }
}

TEST(ReadMeasurements, KcamGivesTheIntrinsicsAndTheFlagReplacesThem) {
  const std::string dir = MakeTempDir("read_meas_kcam");
  const Eigen::MatrixXd w = RandomMatrix(6, 5, 41);
  Eigen::MatrixXd kcam(3, 3);
  kcam << 1056.0, 0.0, 640.0, 0.0, 1050.0, 360.0, 0.0, 0.0, 2.0;  // scaled
  const std::string path = dir + "/kcam.mat";
  ASSERT_TRUE(
      WriteMat(path, MatVersion::kV5, {{"W", w, {}}, {"Kcam", kcam, {}}}).ok());
  Measurements m;
  ASSERT_EQ(Read(path, InputOptions(), &m), "OK");
  ASSERT_EQ(m.intrinsics.cols(), 1);
  EXPECT_EQ(m.intrinsics.col(0), Eigen::Vector4d(528.0, 525.0, 320.0, 180.0));
  InputOptions given;
  ASSERT_TRUE(ParseIntrinsics("500,501,10,20", &given.intrinsics).ok());
  ASSERT_EQ(Read(path, given, &m), "OK");
  EXPECT_EQ(m.intrinsics.col(0), Eigen::Vector4d(500.0, 501.0, 10.0, 20.0));
  // Two groups for one camera, a skew, a bad text: one line naming them.
  ASSERT_TRUE(ParseIntrinsics("1,1,0,0;2,2,0,0", &given.intrinsics).ok());
  EXPECT_TRUE(Contains(Read(path, given, &m), "intrinsics were given for 2"));
  Eigen::Matrix4Xd parsed;
  EXPECT_TRUE(Contains(ParseIntrinsics("500,500,1", &parsed).message(),
                       "intrinsics \"500,500,1\": expected fx,fy,cx,cy"));
  EXPECT_TRUE(Contains(ParseIntrinsics("-5,500,1,1", &parsed).message(),
                       "must be positive"));
  kcam(0, 1) = 3.0;
  const std::string skewed = dir + "/skew.mat";
  ASSERT_TRUE(
      WriteMat(skewed, MatVersion::kV5, {{"W", w, {}}, {"Kcam", kcam, {}}})
          .ok());
  EXPECT_TRUE(Contains(Read(skewed, InputOptions(), &m), "Kcam has a skew"));
}

TEST(ReadMeasurements, LayoutsP3gtAndXAndVariableOverride) {
  const std::string dir = MakeTempDir("read_meas_layouts");
  const int num_frames = 4, num_points = 5;
  // [X_0 … X_3]
  const Eigen::MatrixXd x = RandomMatrix(3, num_points * num_frames, 31);
  Eigen::MatrixXd p3(3 * num_frames, num_points);
  for (int t = 0; t < num_frames; ++t) {
    for (int i = 0; i < 3; ++i)
      p3.row(i * num_frames + t) = x.block(i, t * num_points, 1, num_points);
  }
  const Eigen::MatrixXd other_w = RandomMatrix(2, num_points, 32);
  const std::string path = dir + "/layouts.mat";
  ASSERT_TRUE(WriteMat(path, MatVersion::kV5,
                       {{"X", x, {3, num_points, num_frames}},
                        {"P3_gt", p3, {}},
                        {"W2", other_w, {}},
                        {"X2", x, {3, num_points, num_frames}}})
                  .ok());
  // Auto: no W, so P3_gt comes before X; both give the same W.
  for (const std::string variable : {"", "P3_gt", "X", "X2"}) {
    SCOPED_TRACE(variable);
    InputOptions options;
    options.variable = variable;
    Measurements m;
    ASSERT_EQ(Read(path, options, &m), "OK");
    ASSERT_EQ(m.num_frames, num_frames);
    ASSERT_EQ(m.num_points, num_points);
    for (int t = 0; t < num_frames; ++t) {
      EXPECT_EQ(m.W.row(2 * t), x.block(0, t * num_points, 1, num_points));
      EXPECT_EQ(m.W.row(2 * t + 1), x.block(1, t * num_points, 1, num_points));
    }
  }
  InputOptions options;
  options.variable = "W2";
  Measurements m;
  ASSERT_EQ(Read(path, options, &m), "OK");
  EXPECT_EQ(m.num_frames, 1);
  EXPECT_EQ(m.W, other_w);
}

TEST(ReadMeasurements, TextAndListInputs) {
  const std::string dir = MakeTempDir("read_meas_text");
  std::ofstream(dir + "/w.csv") << "1,2,3\n4,5,6\nNaN,8,9\nNaN,11,12\n";
  Measurements m;
  ASSERT_EQ(Read(dir + "/w.csv", {}, &m), "OK");
  EXPECT_EQ(m.num_frames, 2);
  EXPECT_EQ(m.num_points, 3);
  EXPECT_FALSE(m.visible(1, 0));
  EXPECT_EQ(m.Observation(1, 0, 2), Eigen::Vector2d(9, 12));
  InputOptions two_cameras;
  two_cameras.num_cameras = 2;
  ASSERT_EQ(Read(dir + "/w.csv", two_cameras, &m), "OK");
  EXPECT_EQ(m.num_frames, 1);
  EXPECT_EQ(m.num_cameras, 2);

  std::ofstream(dir + "/w.data") << "0 0 0 1 2\n0 1 1 3 4\n";
  InputOptions list;
  list.format = InputFormat::kList;
  ASSERT_EQ(Read(dir + "/w.data", list, &m), "OK");
  EXPECT_EQ(m.num_cameras, 2);
  EXPECT_EQ(m.NumVisible(), 2);
  list.num_cameras = 3;
  EXPECT_EQ(Read(dir + "/w.data", list, &m),
            dir + "/w.data: the list has 2 camera(s) but num_cameras is 3");
}

// A .mat file's `cameras` variable (nrsfm synth writes it) sets M; a count
// asked for that disagrees is an error naming both; a bad value names the
// file and the variable.
TEST(ReadMeasurements, CamerasComeFromTheFile) {
  const std::string dir = MakeTempDir("read_meas_cameras");
  const Eigen::MatrixXd w = RandomMatrix(12, 5, 43);  // 2FM = 12 rows
  auto write = [&](const std::string& name, const Eigen::MatrixXd& cameras) {
    const std::string path = dir + "/" + name;
    EXPECT_TRUE(WriteMat(path, MatVersion::kV5,
                         {{"W", w, {}}, {"cameras", cameras, {}}})
                    .ok());
    return path;
  };
  const std::string two =
      write("two.mat", Eigen::MatrixXd::Constant(1, 1, 2.0));
  Measurements m;
  ASSERT_EQ(Read(two, {}, &m), "OK");  // num_cameras = 0: from the file
  EXPECT_EQ(m.num_cameras, 2);
  EXPECT_EQ(m.num_frames, 3);
  InputOptions options;
  options.num_cameras = 2;
  ASSERT_EQ(Read(two, options, &m), "OK");
  EXPECT_EQ(m.num_cameras, 2);
  options.num_cameras = 1;
  EXPECT_EQ(
      Read(two, options, &m),
      two +
          ": the file records cameras = 2 (variable 'cameras') but 1 camera(s) "
          "were asked for");
  // The 3-D variables are monocular whatever `cameras` says.
  options = InputOptions();
  const std::string p3 = dir + "/p3.mat";
  ASSERT_TRUE(WriteMat(p3, MatVersion::kV5,
                       {{"P3_gt", RandomMatrix(9, 5, 44), {}},
                        {"cameras", Eigen::MatrixXd::Constant(1, 1, 2.0), {}}})
                  .ok());
  ASSERT_EQ(Read(p3, options, &m), "OK");
  EXPECT_EQ(m.num_cameras, 1);

  EXPECT_EQ(Read(write("half.mat", Eigen::MatrixXd::Constant(1, 1, 2.5)),
                 options, &m),
            dir +
                "/half.mat: variable 'cameras' must be a positive integer (the "
                "number "
                "of cameras M), got 2.5");
  EXPECT_EQ(Read(write("zero.mat", Eigen::MatrixXd::Zero(1, 1)), options, &m),
            dir +
                "/zero.mat: variable 'cameras' must be a positive integer (the "
                "number "
                "of cameras M), got 0");
  EXPECT_EQ(Read(write("pair.mat", Eigen::MatrixXd::Ones(1, 2)), options, &m),
            dir +
                "/pair.mat: variable 'cameras' must be a scalar (the number of "
                "cameras "
                "M), got a 1 x 2 matrix");
  EXPECT_EQ(
      Read(write("four.mat", Eigen::MatrixXd::Constant(1, 1, 4.0)), options,
           &m),
      dir +
          "/four.mat: variable 'cameras' = 4 does not divide the 12 rows of W "
          "into 2 rows per frame and camera");
  EXPECT_TRUE(Contains(
      Read(write("nan.mat", Eigen::MatrixXd::Constant(1, 1, NAN)), options, &m),
      "variable 'cameras' must be a positive integer"));

  // An observation list records its cameras by index: a count that
  // disagrees is an error, 1 included.
  std::ofstream(dir + "/two.obs") << "0 0 0 1 2\n0 1 1 3 4\n";
  ASSERT_EQ(Read(dir + "/two.obs", options, &m), "OK");
  EXPECT_EQ(m.num_cameras, 2);
  options.num_cameras = 1;
  EXPECT_EQ(Read(dir + "/two.obs", options, &m),
            dir + "/two.obs: the list has 2 camera(s) but num_cameras is 1");
}

TEST(ReadMeasurements, BadInputsGiveClearErrors) {
  const std::string dir = MakeTempDir("read_meas_errors");
  const std::string path = dir + "/bad.mat";
  Eigen::MatrixXd one_nan = RandomMatrix(4, 3, 41);
  one_nan(2, 1) = std::nan("");
  Eigen::MatrixXd inf = RandomMatrix(4, 3, 42);
  inf(3, 2) = INFINITY;
  Eigen::MatrixXd u_v_disagree = Eigen::MatrixXd::Ones(4, 3);
  u_v_disagree(1, 0) = 0;
  ASSERT_TRUE(
      WriteMat(path, MatVersion::kV5,
               {{"odd", RandomMatrix(5, 3, 43), {}},
                {"one_nan", one_nan, {}},
                {"inf", inf, {}},
                {"empty", Eigen::MatrixXd(0, 0), {}},
                {"P3_gt", RandomMatrix(8, 3, 44), {}},
                {"X", RandomMatrix(4, 6, 45), {4, 3, 2}},
                {"mask_small", Eigen::MatrixXd::Ones(3, 3), {}},
                {"mask_uv", u_v_disagree, {}},
                {"mask_nan", Eigen::MatrixXd::Constant(2, 3, std::nan("")), {}},
                {"name", Eigen::MatrixXd::Ones(1, 1), {}}})
          .ok());
  struct Case {
    std::string variable, mask;
    int num_cameras;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {"odd", "", 1, path + ": odd: 5 rows is not a multiple of 2"},
      {"one_nan", "", 1,
       path + ": one_nan: only one coordinate of the observation at rows 3-4, "
              "column 2"},
      {"inf", "", 1, path + ": inf: infinite value at row 4, column 3"},
      {"empty", "", 1, path + ": empty is empty (0 x 0)"},
      {"P3_gt", "", 1, path + ": P3_gt has 8 rows, not a multiple of 3"},
      {"X", "", 1, path + ": X is 4 x 3 x 2; expected 3 x P x F"},
      {"nope", "", 1,
       path + ": no variable 'nope'; the file has: odd, one_nan, inf, empty, "
              "P3_gt, X,"},
      {"one_nan", "", 3,
       path + ": one_nan: 4 rows is not a multiple of 2 x 3 cameras"},
      {"inf", "mask_small", 1,
       path + ": mask mask_small is 3 x 3; expected 4 x 3 or 2 x 3"},
      {"inf", "mask_uv", 1,
       path + ": mask mask_uv: rows 1 and 2 (u and v of one view) differ at "
              "column 1"},
      {"inf", "mask_nan", 1, path + ": mask mask_nan holds NaN or Inf"},
      {"inf", "missing_mask", 1, path + ": no variable 'missing_mask'"},
  };
  for (const Case& c : cases) {
    InputOptions options;
    options.variable = c.variable;
    options.mask_variable = c.mask;
    options.num_cameras = c.num_cameras;
    Measurements m;
    const std::string message = Read(path, options, &m);
    EXPECT_TRUE(Contains(message, c.expected))
        << message << "\nexpected: " << c.expected;
  }
  // The mask can hide the Inf: masked-out entries are never looked at.
  InputOptions masked;
  masked.variable = "inf";
  Eigen::MatrixXd hide = Eigen::MatrixXd::Ones(2, 3);
  hide(1, 2) = 0;
  ASSERT_TRUE(WriteMat(dir + "/hide.mat", MatVersion::kV4,
                       {{"inf", inf, {}}, {"m", hide, {}}})
                  .ok());
  masked.mask_variable = "m";
  Measurements m;
  EXPECT_EQ(Read(dir + "/hide.mat", masked, &m), "OK");
  EXPECT_EQ(m.NumVisible(), 5);

  // No usable variable at all.
  InputOptions auto_options;
  const std::string no_w = dir + "/no_w.mat";
  ASSERT_TRUE(
      WriteMat(no_w, MatVersion::kV73, {{"A", Eigen::MatrixXd::Ones(2, 2), {}}})
          .ok());
  EXPECT_EQ(Read(no_w, auto_options, &m),
            no_w +
                ": none of the variables W, P3_gt, X is in the file (it has: "
                "A); name one");
  // Formats and options.
  EXPECT_TRUE(
      Contains(Read(dir + "/w.xyz", auto_options, &m),
               "cannot tell the input format from the extension '.xyz'"));
  std::ofstream(dir + "/w.txt") << "1 2\n3 4\n";
  InputOptions text_with_var;
  text_with_var.variable = "W";
  EXPECT_TRUE(Contains(Read(dir + "/w.txt", text_with_var, &m),
                       "can only be named for .mat input"));
  InputFormat format = InputFormat::kAuto;
  EXPECT_EQ(ParseInputFormat("xml", &format).message(),
            "input format: unknown value \"xml\" (expected one of auto, mat, "
            "text, list, coco, "
            "openpose)");
  ASSERT_TRUE(ParseInputFormat("list", &format).ok());
  EXPECT_EQ(format, InputFormat::kList);
  EXPECT_STREQ(InputFormatName(InputFormat::kText), "text");
  InputOptions bad_format;
  bad_format.format = static_cast<InputFormat>(7);
  EXPECT_TRUE(
      Contains(Read(dir + "/w.txt", bad_format, &m), "invalid format 7"));
  InputOptions negative_cameras;  // 0 = from the file
  negative_cameras.num_cameras = -1;
  EXPECT_TRUE(
      Contains(negative_cameras.Check().message(),
               "num_cameras must be >= 1 (or 0: from the file), got -1"));
  InputOptions p3_two_cameras;
  p3_two_cameras.variable = "X";
  p3_two_cameras.num_cameras = 2;
  ASSERT_TRUE(WriteMat(dir + "/x.mat", MatVersion::kV5,
                       {{"X", RandomMatrix(3, 8, 46), {3, 4, 2}}})
                  .ok());
  EXPECT_EQ(Read(dir + "/x.mat", p3_two_cameras, &m),
            dir + "/x.mat: X holds monocular data; num_cameras must be 1");
  // A text file given the .mat extension.
  std::ofstream(dir + "/text.mat") << "1 2\n3 4\n";
  EXPECT_TRUE(Contains(Read(dir + "/text.mat", auto_options, &m),
                       dir + "/text.mat: not a MATLAB .mat file"));
}

// Variables with a zero-sized dimension, empty masks, and cells and structs
// (empty or with empty fields), written byte by byte: each gives the one
// error line naming the file and the variable; none may be indexed.
TEST(ReadMeasurements, EmptyVariablesGiveTheOneLineError) {
  namespace v5 = testing_util::v5;
  const std::string dir = MakeTempDir("read_meas_empty");
  struct Case {
    std::string file, variable_bytes, variable, expected;
  };
  const std::vector<Case> cases = {
      {"w_0xp", v5::Double("W", {0, 3}, {}), "W", "W is empty (0 x 3)"},
      {"w_2fx0", v5::Double("W", {4, 0}, {}), "W", "W is empty (4 x 0)"},
      // The crash of issue 18: a 3-D W with no slice.
      {"w_4x3x0", v5::Double("W", {4, 3, 0}, {}), "W",
       "W is empty (4 x 3 x 0)"},
      {"w_0x0x0", v5::Double("W", {0, 0, 0}, {}), "W",
       "W is empty (0 x 0 x 0)"},
      {"w_0x3x2", v5::Double("W", {0, 3, 2}, {}), "W",
       "W is empty (0 x 3 x 2)"},
      {"x_3xpx0", v5::Double("X", {3, 4, 0}, {}), "X",
       "X is empty (3 x 4 x 0)"},
      {"x_3x0xf", v5::Double("X", {3, 0, 2}, {}), "X",
       "X is empty (3 x 0 x 2)"},
      {"x_0xpxf", v5::Double("X", {0, 4, 2}, {}), "X",
       "X is empty (0 x 4 x 2)"},
      {"x_3x0", v5::Double("X", {3, 0}, {}), "X", "X is empty (3 x 0)"},
      {"p3_0xp", v5::Double("P3_gt", {0, 4}, {}), "P3_gt",
       "P3_gt is empty (0 x 4)"},
      {"p3_3fx0", v5::Double("P3_gt", {6, 0}, {}), "P3_gt",
       "P3_gt is empty (6 x 0)"},
      {"w_cell_0x0", v5::Cell("W", {0, 0}, {}), "W",
       "variable 'W' is a cell array, not a numeric array"},
      {"w_cell_empty", v5::Cell("W", {1, 1}, {v5::EmptyMatrix()}), "W",
       "variable 'W' is a cell array, not a numeric array"},
      {"w_struct_empty_field",
       v5::Struct("W", {"data", "empty"},
                  {v5::Double("", {0, 0}, {}), v5::EmptyMatrix()}),
       "W", "variable 'W' is a struct, not a numeric array"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    const std::string path = dir + "/" + c.file + ".mat";
    WriteBytes(path, v5::Header() + c.variable_bytes);
    Measurements m;
    // Found by name and by the automatic choice of W, P3_gt, X.
    InputOptions named;
    named.variable = c.variable;
    EXPECT_EQ(Read(path, named, &m), path + ": " + c.expected);
    EXPECT_EQ(Read(path, InputOptions(), &m), path + ": " + c.expected);
  }

  // Empty masks of a good W (2F x P = 4 x 3); an empty W ignores the mask.
  const std::string w = v5::Double("W", {4, 3}, std::vector<double>(12, 1.0));
  const std::string path = dir + "/masks.mat";
  WriteBytes(path, v5::Header() + w + v5::Double("m_0x0", {0, 0}, {}) +
                       v5::Double("m_0xp", {0, 3}, {}) +
                       v5::Double("m_fx0", {2, 0}, {}) +
                       v5::Double("m_2x3x0", {2, 3, 0}, {}) +
                       v5::Cell("m_cell", {0, 0}, {}) +
                       v5::Struct("m_struct", {"e"}, {v5::EmptyMatrix()}) +
                       v5::Double("W_empty", {0, 3}, {}));
  const std::string shape = "; expected 4 x 3 or 2 x 3 (W is 4 x 3, M = 1)";
  const std::vector<std::pair<std::string, std::string>> masks = {
      {"m_0x0", "mask m_0x0 is 0 x 0" + shape},
      {"m_0xp", "mask m_0xp is 0 x 3" + shape},
      {"m_fx0", "mask m_fx0 is 2 x 0" + shape},
      {"m_2x3x0",
       "variable 'm_2x3x0' is 3-D (2 x 3 x 0); expected a 2-D matrix"},
      {"m_cell", "variable 'm_cell' is a cell array, not a numeric array"},
      {"m_struct", "variable 'm_struct' is a struct, not a numeric array"},
  };
  for (const auto& [mask, expected] : masks) {
    InputOptions options;
    options.mask_variable = mask;
    Measurements m;
    EXPECT_EQ(Read(path, options, &m), path + ": " + expected);
  }
  InputOptions empty_w;
  empty_w.variable = "W_empty";
  empty_w.mask_variable = "m_0x0";
  Measurements m;
  EXPECT_EQ(Read(path, empty_w, &m), path + ": W_empty is empty (0 x 3)");
}

}  // namespace
}  // namespace nrsfm
