#include "core/io/ground_truth.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "core/io/mat_io.h"
#include "core/io/read_measurements.h"
#include "core/math/rotation.h"
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
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::MatrixXd m(rows, cols);
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = uniform(rng);
  return m;
}

// The first two rows of F rotations (2F × 3), seeded.
Eigen::MatrixXd RandomRotationRows(int num_frames, std::uint32_t seed) {
  const Eigen::MatrixXd angles = RandomMatrix(num_frames, 3, seed);
  Eigen::MatrixXd rows(2 * num_frames, 3);
  for (int t = 0; t < num_frames; ++t) {
    rows.middleRows<2>(2 * t) =
        AngleAxisToRotation(angles.row(t).transpose()).topRows<2>();
  }
  return rows;
}

TEST(GroundTruth, DrinkSAndRsReproduceW) {
  NRSFM_SKIP_WITHOUT_SHARED_DATA(dir);
  const std::string path = dir + "/drink.mat";
  GroundTruth truth;
  ASSERT_TRUE(ReadGroundTruth(path, "", &truth).ok());
  EXPECT_EQ(truth.source, "S+Rs");
  ASSERT_EQ(truth.NumFrames(), 1102);
  ASSERT_EQ(truth.NumPoints(), 41);
  Measurements m;
  ASSERT_TRUE(ReadMeasurements(path, {}, &m).ok());
  Eigen::MatrixXd s;
  ASSERT_TRUE(ReadMatVariable(path, "S", &s).ok());
  double max_w_error = 0.0, max_norm_error = 0.0;
  for (int t = 0; t < truth.NumFrames(); ++t) {
    // Rows 0, 1 of the camera-frame truth are Rs_t S_t = W_t.
    max_w_error = std::max(
        max_w_error,
        (truth.points_in_camera[t].topRows<2>() - m.W.middleRows(2 * t, 2))
            .cwiseAbs()
            .maxCoeff());
    // A rotation keeps every point's distance to the origin.
    max_norm_error =
        std::max(max_norm_error, (truth.points_in_camera[t].colwise().norm() -
                                  s.middleRows(3 * t, 3).colwise().norm())
                                     .cwiseAbs()
                                     .maxCoeff());
  }
  // W is in [-1, 1]; measured max |Rs_t S_t - W_t| is 1.7e-16.
  EXPECT_LT(max_w_error, 1e-14);
  EXPECT_LT(max_norm_error, 1e-14);
}

TEST(GroundTruth, FaceP3gtIsTheBlockLayout) {
  NRSFM_SKIP_WITHOUT_SHARED_DATA(dir);
  const std::string path = dir + "/face.mat";
  GroundTruth truth;
  ASSERT_TRUE(ReadGroundTruth(path, "", &truth).ok());
  EXPECT_EQ(truth.source, "P3_gt");
  ASSERT_EQ(truth.NumFrames(), 316);
  ASSERT_EQ(truth.NumPoints(), 40);
  Eigen::MatrixXd p3;
  ASSERT_TRUE(ReadMatVariable(path, "P3_gt", &p3).ok());
  for (int t : {0, 1, 157, 315}) {
    EXPECT_EQ(truth.points_in_camera[t].row(0), p3.row(t));
    EXPECT_EQ(truth.points_in_camera[t].row(1), p3.row(316 + t));
    EXPECT_EQ(truth.points_in_camera[t].row(2), p3.row(632 + t));  // z rows
  }
  EXPECT_EQ(truth.points_in_camera[0](2, 0),
            290.10717773437500);  // hand-read z
}

TEST(GroundTruth, SyntheticSAndRsP3gtAndXAgree) {
  // One camera-frame truth written in all three layouts must read back the
  // same; S + Rs uses a known rotation per frame.
  const int num_frames = 3, num_points = 4;
  std::vector<Eigen::Matrix3Xd> camera(num_frames);
  Eigen::MatrixXd s(3 * num_frames, num_points), rs(2 * num_frames, 3);
  Eigen::MatrixXd p3(3 * num_frames, num_points), x(3, num_frames * num_points);
  for (int t = 0; t < num_frames; ++t) {
    const Eigen::Matrix3d r =
        AngleAxisToRotation(Eigen::Vector3d(0.3 * t, -0.5, 1.0 + t));
    const Eigen::Matrix3Xd world = RandomMatrix(3, num_points, 50 + t);
    camera[t] = r * world;
    s.middleRows(3 * t, 3) = world;
    rs.middleRows(2 * t, 2) = r.topRows<2>();
    for (int i = 0; i < 3; ++i) p3.row(i * num_frames + t) = camera[t].row(i);
    x.middleCols(t * num_points, num_points) = camera[t];
  }
  const std::string dir = MakeTempDir("ground_truth_synthetic");
  const std::string all = dir + "/all.mat";
  ASSERT_TRUE(WriteMat(all, MatVersion::kV73,
                       {{"S", s, {}},
                        {"Rs", rs, {}},
                        {"P3_gt", p3, {}},
                        {"X", x, {3, num_points, num_frames}}})
                  .ok());
  for (const std::string variable : {"", "S", "P3_gt", "X"}) {
    SCOPED_TRACE(variable);
    GroundTruth truth;
    ASSERT_TRUE(ReadGroundTruth(all, variable, &truth).ok());
    EXPECT_EQ(truth.source,
              variable.empty() || variable == "S" ? "S+Rs" : variable);
    ASSERT_EQ(truth.NumFrames(), num_frames);
    for (int t = 0; t < num_frames; ++t) {
      EXPECT_LT((truth.points_in_camera[t] - camera[t]).cwiseAbs().maxCoeff(),
                1e-15);
    }
    // Only S + Rs has an object (world) frame: S itself and the rotations.
    EXPECT_EQ(truth.HasObjectFrame(), truth.source == "S+Rs");
    if (truth.HasObjectFrame()) {
      for (int t = 0; t < num_frames; ++t) {
        EXPECT_EQ(truth.points_in_object[t], s.middleRows(3 * t, 3));
        EXPECT_LT((truth.rotations[t].topRows<2>() - rs.middleRows(2 * t, 2))
                      .cwiseAbs()
                      .maxCoeff(),
                  1e-15);
      }
    }
  }
  // Without S and Rs, P3_gt is preferred to X.
  const std::string no_s = dir + "/no_s.mat";
  ASSERT_TRUE(
      WriteMat(no_s, MatVersion::kV5,
               {{"X", x, {3, num_points, num_frames}}, {"P3_gt", p3, {}}})
          .ok());
  GroundTruth truth;
  ASSERT_TRUE(ReadGroundTruth(no_s, "", &truth).ok());
  EXPECT_EQ(truth.source, "P3_gt");
}

TEST(GroundTruth, BadInputsGiveClearErrors) {
  const std::string dir = MakeTempDir("ground_truth_errors");
  const std::string path = dir + "/bad.mat";
  Eigen::MatrixXd s_nan = RandomMatrix(6, 4, 61);
  s_nan(4, 1) = std::nan("");
  ASSERT_TRUE(WriteMat(path, MatVersion::kV5,
                       {{"S", RandomMatrix(6, 4, 60), {}},
                        {"Rs", RandomMatrix(6, 3, 62), {}},
                        {"P3_gt", RandomMatrix(7, 4, 63), {}},
                        {"X", RandomMatrix(2, 8, 64), {2, 4, 2}}})
                  .ok());
  GroundTruth truth;
  Status st = ReadGroundTruth(path, "S", &truth);
  EXPECT_TRUE(Contains(
      st.message(),
      path + ": Rs is 6 x 3; expected 2F x 3 = 4 x 3 for S with 6 rows"))
      << st.message();
  st = ReadGroundTruth(path, "P3_gt", &truth);
  EXPECT_TRUE(
      Contains(st.message(), path + ": P3_gt has 7 rows, not a multiple of 3"))
      << st.message();
  st = ReadGroundTruth(path, "X", &truth);
  EXPECT_TRUE(
      Contains(st.message(), path + ": X is 2 x 4 x 2; expected 3 x P x F"))
      << st.message();
  st = ReadGroundTruth(path, "W", &truth);
  EXPECT_TRUE(Contains(st.message(), "'W' is not a ground-truth variable"))
      << st.message();

  const std::string nan_path = dir + "/nan.mat";
  ASSERT_TRUE(
      WriteMat(nan_path, MatVersion::kV4,
               {{"S", s_nan, {}}, {"Rs", RandomRotationRows(2, 62), {}}})
          .ok());
  st = ReadGroundTruth(nan_path, "", &truth);
  EXPECT_EQ(st.message(),
            nan_path + ": ground truth S holds NaN or Inf (frame 1)");

  // Rs rows that are not a rotation's (here scaled by 2 in frame 1).
  const std::string sheared = dir + "/sheared.mat";
  Eigen::MatrixXd rs_scaled = RandomRotationRows(2, 67);
  rs_scaled.middleRows<2>(2) *= 2.0;
  ASSERT_TRUE(
      WriteMat(sheared, MatVersion::kV5,
               {{"S", RandomMatrix(6, 4, 68), {}}, {"Rs", rs_scaled, {}}})
          .ok());
  st = ReadGroundTruth(sheared, "", &truth);
  EXPECT_EQ(st.message(), sheared +
                              ": Rs rows 3-4 (frame 1) are not two "
                              "orthonormal rows of a rotation");

  const std::string none = dir + "/none.mat";
  ASSERT_TRUE(WriteMat(none, MatVersion::kV5,
                       {{"W", RandomMatrix(4, 4, 65), {}},
                        {"S", RandomMatrix(6, 4, 66), {}}})
                  .ok());
  st = ReadGroundTruth(none, "", &truth);
  EXPECT_EQ(st.message(), none +
                              ": no ground truth (S with Rs, P3_gt or X) in "
                              "the file; it has: W, S");
  st = ReadGroundTruth(none, "S", &truth);
  EXPECT_EQ(st.message(), none + ": no variable 'Rs'; the file has: W, S");
  st = ReadGroundTruth(dir + "/missing.mat", "", &truth);
  EXPECT_EQ(st.message(), dir + "/missing.mat: no such file");
}

// Truth variables with a zero-sized dimension, and cells and structs (empty
// or with empty fields), written byte by byte: one error line naming the
// file and the variable, never an index into an empty array.
TEST(GroundTruth, EmptyVariablesGiveTheOneLineError) {
  namespace v5 = testing_util::v5;
  const std::string dir = MakeTempDir("ground_truth_empty");
  const std::vector<double> rotation_rows = {1, 0, 0, 1, 0, 0};  // 2 x 3
  const std::string rs = v5::Double("Rs", {2, 3}, rotation_rows);
  const std::string s = v5::Double("S", {3, 2}, {1, 2, 3, 4, 5, 7});
  struct Case {
    std::string file, variables, expected;
  };
  const std::vector<Case> cases = {
      {"x_3xpx0", v5::Double("X", {3, 4, 0}, {}),
       "X is empty (3 x 4 x 0); expected a 3 x P x F array"},
      {"x_3x0xf", v5::Double("X", {3, 0, 2}, {}),
       "X is empty (3 x 0 x 2); expected a 3 x P x F array"},
      {"x_0xpxf", v5::Double("X", {0, 4, 2}, {}),
       "X is empty (0 x 4 x 2); expected a 3 x P x F array"},
      {"p3_0xp", v5::Double("P3_gt", {0, 4}, {}), "P3_gt is empty (0 x 4)"},
      {"p3_3fx0", v5::Double("P3_gt", {3, 0}, {}), "P3_gt is empty (3 x 0)"},
      {"s_0xp", v5::Double("S", {0, 4}, {}) + rs, "S is empty (0 x 4)"},
      {"s_3fx0", v5::Double("S", {3, 0}, {}) + rs, "S is empty (3 x 0)"},
      {"rs_0x3", s + v5::Double("Rs", {0, 3}, {}),
       "Rs is 0 x 3; expected 2F x 3 = 2 x 3 for S with 3 rows (F = 1)"},
      {"rs_2fx0", s + v5::Double("Rs", {2, 0}, {}),
       "Rs is 2 x 0; expected 2F x 3 = 2 x 3 for S with 3 rows (F = 1)"},
      {"rs_cell", s + v5::Cell("Rs", {0, 0}, {}),
       "variable 'Rs' is a cell array, not a numeric array"},
      {"x_cell", v5::Cell("X", {1, 2}, {v5::EmptyMatrix(), v5::EmptyMatrix()}),
       "variable 'X' is a cell array, not a numeric array"},
      {"x_struct", v5::Struct("X", {"empty"}, {v5::EmptyMatrix()}),
       "variable 'X' is a struct, not a numeric array"},
      {"s_struct",
       v5::Struct("S", {"a", "b"},
                  {v5::Double("", {0, 3}, {}), v5::EmptyMatrix()}) +
           rs,
       "variable 'S' is a struct, not a numeric array"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    const std::string path = dir + "/" + c.file + ".mat";
    {
      const std::string bytes = v5::Header() + c.variables;
      std::ofstream(path, std::ios::binary).write(bytes.data(), bytes.size());
    }
    GroundTruth truth;
    const Status st = ReadGroundTruth(path, "", &truth);
    EXPECT_EQ(st.message(), path + ": " + c.expected);
  }
}

}  // namespace
}  // namespace nrsfm
