#include "core/io/text_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include "tests/test_util.h"

namespace nrsfm {
namespace {

using testing_util::MakeTempDir;

std::string WriteFile(const std::string& dir, const std::string& name,
                      const std::string& text) {
  const std::string path = dir + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(TextMatrix, ParsesSeparatorsCommentsAndNaN) {
  const std::string dir = MakeTempDir("text_matrix_parse");
  const std::string path = WriteFile(dir, "w.csv",
                                     "# a comment line\n"
                                     "\n"
                                     "1, 2.5 ,-3e-2\r\n"
                                     "  +4\t5,NaN   # trailing comment\n"
                                     "nan,1e300 7\n");
  Eigen::MatrixXd m;
  ASSERT_TRUE(ReadTextMatrix(path, &m).ok());
  ASSERT_EQ(m.rows(), 3);
  ASSERT_EQ(m.cols(), 3);
  EXPECT_EQ(m(0, 0), 1.0);
  EXPECT_EQ(m(0, 1), 2.5);
  EXPECT_EQ(m(0, 2), -0.03);
  EXPECT_EQ(m(1, 0), 4.0);
  EXPECT_EQ(m(1, 1), 5.0);
  EXPECT_TRUE(std::isnan(m(1, 2)));
  EXPECT_TRUE(std::isnan(m(2, 0)));
  EXPECT_EQ(m(2, 1), 1e300);
  EXPECT_EQ(m(2, 2), 7.0);
}

TEST(TextMatrix, WriteThenReadIsBitIdentical) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, 1e3);
  Eigen::MatrixXd m(7, 4);
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = normal(rng);
  m(2, 3) = std::nan("");
  m(0, 0) = 1.0 / 3.0;
  m(6, 1) = -4.9e-324;  // smallest subnormal
  const std::string path = MakeTempDir("text_matrix_round_trip") + "/w.txt";
  ASSERT_TRUE(WriteTextMatrix(path, m).ok());
  Eigen::MatrixXd read;
  ASSERT_TRUE(ReadTextMatrix(path, &read).ok());
  ASSERT_EQ(read.rows(), m.rows());
  ASSERT_EQ(read.cols(), m.cols());
  EXPECT_EQ(std::memcmp(read.data(), m.data(), sizeof(double) * m.size()), 0);
}

TEST(TextWriter, WritesTheShortestFormThatReadsBackAndReportsWriteErrors) {
  const std::string path = MakeTempDir("text_writer") + "/out.txt";
  {
    TextWriter out;
    ASSERT_TRUE(out.Open(path).ok());
    out.Int(-12).Char(' ').Number(0.1).Char(' ').Number(3.0).Char(' ');
    out.Number(-2.5e-7).Char(' ').Number(std::nan("")).Char(' ');
    out.Number(std::nan(""), "NaN").Char(' ').Number(1.0 / 3.0).Char(' ');
    out.Number(1.7976931348623157e308).Char(' ').Number(-0.0).Text("\n");
    ASSERT_TRUE(out.Close().ok());
  }
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)),
                   std::istreambuf_iterator<char>());
  EXPECT_EQ(text,
            "-12 0.1 3 -2.5e-07 nan NaN 0.3333333333333333 "
            "1.7976931348623157e+308 -0\n");

  // More than the buffer holds, in one file: every value reads back.
  std::mt19937 rng(5);
  std::normal_distribution<double> normal(0.0, 1e4);
  Eigen::MatrixXd m(20000, 9);
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = normal(rng);
  ASSERT_TRUE(WriteTextMatrix(path, m).ok());
  Eigen::MatrixXd read;
  ASSERT_TRUE(ReadTextMatrix(path, &read).ok());
  ASSERT_EQ(read.rows(), m.rows());
  EXPECT_EQ(std::memcmp(read.data(), m.data(), sizeof(double) * m.size()), 0);

  // A full device: Close() names the file.
  if (std::ifstream("/dev/full").good()) {
    TextWriter out;
    ASSERT_TRUE(out.Open("/dev/full").ok());
    for (int i = 0; i < 300000; ++i) out.Number(i + 0.5).Char('\n');
    const Status status = out.Close();
    ASSERT_FALSE(status.ok());
    EXPECT_TRUE(Contains(status.message(), "/dev/full: error while writing"))
        << status.message();
  }
  TextWriter missing;
  const Status status = missing.Open("/nonexistent-dir/x.txt");
  ASSERT_FALSE(status.ok());
  EXPECT_TRUE(
      Contains(status.message(), "/nonexistent-dir/x.txt: cannot create"))
      << status.message();
}

TEST(TextMatrix, BadInputsNameLineAndColumn) {
  const std::string dir = MakeTempDir("text_matrix_errors");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"1 2 3\n# note\n4 5\n", "line 3 has 2 values, expected 3 as on line 1"},
      {"1 2\n3 abc\n", "line 2, column 2: 'abc' is not a number"},
      {"1 2\n3 4x\n", "line 2, column 2: '4x' is not a number"},
      {"1 2\nInf 4\n", "line 2, column 1: infinite value 'Inf'; use NaN"},
      {"1 -inf\n", "line 1, column 2: infinite value '-inf'"},
      {"1,,2\n", "line 1, column 2: empty field"},
      {"1,2,\n", "line 1, column 3: empty field"},
      {"1 1e999\n", "line 1, column 2: '1e999' is out of the range of double"},
      {"# only a comment\n\n", "no numbers in the file"},
      {"", "no numbers in the file"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string path =
        WriteFile(dir, "case" + std::to_string(i) + ".txt", cases[i].first);
    Eigen::MatrixXd m;
    const Status s = ReadTextMatrix(path, &m);
    EXPECT_FALSE(s.ok()) << i;
    EXPECT_TRUE(Contains(s.message(), path + ": " + cases[i].second))
        << s.message();
  }
  Eigen::MatrixXd m;
  EXPECT_EQ(ReadTextMatrix(dir + "/none.txt", &m).message(),
            dir + "/none.txt: no such file");
  EXPECT_EQ(ReadTextMatrix(dir, &m).message(),
            dir + ": is a directory, not a text file");
}

TEST(CsvTable, ChecksTheHeader) {
  const std::string dir = MakeTempDir("csv_table");
  const std::string good =
      WriteFile(dir, "good.csv", "frame,point,x\n0,1,2.5\n1,0,-1\n");
  Eigen::MatrixXd table;
  ASSERT_TRUE(ReadCsvTable(good, {"frame", "point", "x"}, &table).ok());
  EXPECT_EQ(table, (Eigen::MatrixXd(2, 3) << 0, 1, 2.5, 1, 0, -1).finished());
  Status s = ReadCsvTable(good, {"frame", "point", "y"}, &table);
  EXPECT_EQ(s.message(), good + ": line 1: expected the header frame,point,y");
  const std::string short_row = WriteFile(dir, "short.csv", "a,b\n1,2\n3\n");
  s = ReadCsvTable(short_row, {"a", "b"}, &table);
  EXPECT_EQ(s.message(), short_row + ": line 3 has 1 values, expected 2");
}

TEST(ObservationList, ReadsSizesFromTheLargestIndices) {
  const std::string path =
      WriteFile(MakeTempDir("obs_list"), "tracks.obs",
                "# frame camera point u v\n"
                "0 0 0 1.5 -2\n"
                "0,1,2, 3,4\n"
                "2 1 0 5 6   # frame 1 has no observation\n"
                "2.0 0 2 7 8\n");
  Measurements m;
  ASSERT_TRUE(ReadObservationList(path, &m).ok());
  EXPECT_EQ(m.num_frames, 3);
  EXPECT_EQ(m.num_cameras, 2);
  EXPECT_EQ(m.num_points, 3);
  EXPECT_EQ(m.NumVisible(), 4);
  EXPECT_TRUE(m.Validate().ok());
  EXPECT_EQ(m.Observation(0, 0, 0), Eigen::Vector2d(1.5, -2));
  EXPECT_EQ(m.Observation(0, 1, 2), Eigen::Vector2d(3, 4));
  EXPECT_EQ(m.Observation(2, 1, 0), Eigen::Vector2d(5, 6));
  EXPECT_EQ(m.Observation(2, 0, 2), Eigen::Vector2d(7, 8));
  EXPECT_EQ(m.VisiblePerView()(m.View(1, 0)) + m.VisiblePerView()(m.View(1, 1)),
            0);
  EXPECT_TRUE(std::isnan(m.W(2 * m.View(1, 0), 0)));
  // Within the budget the list's own indices are kept.
  EXPECT_TRUE(m.frame_ids.empty());
  EXPECT_TRUE(m.point_ids.empty());
}

// A list whose largest indices would make a W over the budget (64 MB +
// 1032 bytes per byte of the file) keeps only the frames and points it
// mentions, with their indices: two lines with frame 1 300 000 took 2 GB
// as 1 300 001 frames. Written back, it has the list's indices again.
TEST(ObservationList, TooSparseForItsIndicesKeepsTheFramesAndPointsItMentions) {
  const std::string dir = MakeTempDir("obs_sparse");
  const std::string path =
      WriteFile(dir, "two.obs", "0 0 0 1 2\n1300000 0 99 1.0 2.0\n");
  Measurements m;
  ASSERT_TRUE(ReadObservationList(path, &m).ok());
  EXPECT_EQ(m.num_frames, 2);
  EXPECT_EQ(m.num_cameras, 1);
  EXPECT_EQ(m.num_points, 2);
  EXPECT_EQ(m.frame_ids, (std::vector<int>{0, 1300000}));
  EXPECT_EQ(m.point_ids, (std::vector<int>{0, 99}));
  EXPECT_TRUE(m.Validate().ok());
  EXPECT_EQ(m.NumVisible(), 2);
  EXPECT_EQ(m.Observation(0, 0, 0), Eigen::Vector2d(1, 2));
  EXPECT_EQ(m.Observation(1, 0, 1), Eigen::Vector2d(1, 2));
  EXPECT_FALSE(m.visible(m.View(0, 0), 1));

  const std::string copy = dir + "/copy.obs";
  ASSERT_TRUE(WriteObservationList(copy, m).ok());
  EXPECT_TRUE(
      Contains(testing_util::ReadFileToString(copy), "\n1300000 0 99 1 2\n"));
  Measurements read;
  ASSERT_TRUE(ReadObservationList(copy, &read).ok());
  EXPECT_EQ(read.frame_ids, m.frame_ids);
  EXPECT_EQ(read.point_ids, m.point_ids);
  EXPECT_TRUE((read.visible == m.visible).all());
  EXPECT_EQ(read.Observation(1, 0, 1), m.Observation(1, 0, 1));
}

// Even the frames and points it mentions can make a W over the budget: a
// "diagonal" list of 3000 frames that each see another point (17 bytes an
// entry of W and mask: 153 MB for a 51 kB file).
TEST(ObservationList, TooSparseEvenForTheMentionedFramesAndPointsIsAnError) {
  std::string text;
  for (int i = 0; i < 3000; ++i) {
    text += std::to_string(i) + " 0 " + std::to_string(i) + " 1 2\n";
  }
  const std::string path =
      WriteFile(MakeTempDir("obs_diagonal"), "diagonal.obs", text);
  Measurements m;
  const Status s = ReadObservationList(path, &m);
  EXPECT_TRUE(Contains(
      s.message(),
      path + ": the 3000 observations of F = 3000 frames, M = 1 cameras and "
             "P = 3000 points would need a W of 153 MB, more than a list of "
             "its size may take ("))
      << s.message();
  EXPECT_TRUE(Contains(s.message(), "too sparse for nrsfm's dense W"))
      << s.message();
}

TEST(ObservationList, WriteThenReadKeepsEveryObservation) {
  Measurements m;
  m.num_frames = 3;
  m.num_cameras = 2;
  m.num_points = 4;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(-500.0, 500.0);
  m.W.resize(12, 4);
  for (Eigen::Index i = 0; i < m.W.size(); ++i) m.W.data()[i] = uniform(rng);
  m.visible.setConstant(6, 4, true);
  m.visible(1, 2) = false;
  m.visible(4, 0) = false;
  m.W.col(2).segment(2, 2).setConstant(std::nan(""));
  m.W.col(0).segment(8, 2).setConstant(std::nan(""));
  const std::string path = MakeTempDir("obs_round_trip") + "/m.list";
  ASSERT_TRUE(WriteObservationList(path, m).ok());
  Measurements read;
  ASSERT_TRUE(ReadObservationList(path, &read).ok());
  EXPECT_EQ(read.num_frames, 3);
  EXPECT_EQ(read.num_cameras, 2);
  EXPECT_EQ(read.num_points, 4);
  EXPECT_TRUE((read.visible == m.visible).all());
  for (int view = 0; view < 6; ++view) {
    for (int p = 0; p < 4; ++p) {
      if (!m.visible(view, p)) continue;
      EXPECT_EQ(read.W(2 * view, p), m.W(2 * view, p));
      EXPECT_EQ(read.W(2 * view + 1, p), m.W(2 * view + 1, p));
    }
  }
}

TEST(ObservationList, BadInputsNameTheLine) {
  const std::string dir = MakeTempDir("obs_errors");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"0 0 0 1 2\n0 0 -1 1 2\n",
       "line 2, column 3: point index '-1' is negative"},
      {"0 0 0 1 2\n1.5 0 0 1 2\n",
       "line 2, column 1: frame index '1.5' is not an integer"},
      {"0 nan 0 1 2\n",
       "line 1, column 2: camera index 'nan' is not an integer"},
      {"0 0 3e9 1 2\n", "line 1, column 3: point index '3e9' is too large"},
      {"0 0 0 1 2\n# c\n0 0 0 3 4\n",
       "line 3: frame 0, camera 0, point 0 was already given on line 1"},
      {"0 0 0 1\n", "line 1 has 4 fields; expected 5: frame camera point u v"},
      {"0 0 0 1 NaN\n", "line 1: u and v must be numbers"},
      {"0 0 0 1 inf\n", "line 1, column 5: infinite value"},
      {"0 0 zero 1 2\n", "line 1, column 3: 'zero' is not a number"},
      {"# nothing\n", "no observations in the file"},
      // The first repeat in file order (line 3), not in index order.
      {"5 0 0 1 2\n0 0 0 1 2\n5 0 0 3 4\n0 0 0 3 4\n",
       "line 3: frame 5, camera 0, point 0 was already given on line 1"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string path =
        WriteFile(dir, "case" + std::to_string(i) + ".obs", cases[i].first);
    Measurements m;
    const Status s = ReadObservationList(path, &m);
    EXPECT_FALSE(s.ok()) << i;
    EXPECT_TRUE(Contains(s.message(), path + ": " + cases[i].second))
        << s.message();
  }
}

}  // namespace
}  // namespace nrsfm
