#include "core/io/mat_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "tests/mat_v5_bytes.h"
#include "tests/test_util.h"

namespace nrsfm {
namespace {

using testing_util::MakeTempDir;

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Bit-identical, NaN included.
bool SameBits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         (a.size() ==
              0 ||  // memcmp must not see an empty matrix's null pointer
          std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0);
}

Eigen::MatrixXd RandomMatrix(int rows, int cols, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 100.0);
  Eigen::MatrixXd m(rows, cols);
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = normal(rng);
  return m;
}

void WriteBytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// --- Hand-made MATLAB files (little endian), for classes WriteMat cannot
// write. v5: tests/mat_v5_bytes.h (Header, Element, Matrix, kMi*, kMx*).
// v4: 5 int32 (MOPT, rows, cols, imagf, name length), name, data.
using namespace testing_util::v5;

std::string V4Variable(const std::string& name, int rows, int cols,
                       int precision, int type, const std::string& data,
                       bool complex = false) {
  const std::vector<std::int32_t> header = {
      precision * 10 + type, rows, cols, complex ? 1 : 0,
      static_cast<std::int32_t>(name.size() + 1)};
  return Raw(header) + name + std::string(1, '\0') + data +
         (complex ? data : "");
}

// --- Round trips through WriteMat.

TEST(MatIo, RoundTripIsBitIdenticalInEveryVersion) {
  const std::string dir = MakeTempDir("mat_io_round_trip");
  Eigen::MatrixXd w = RandomMatrix(8, 5, 7);
  w(3, 2) = std::nan("");
  w(0, 4) = std::nan("");
  w(7, 0) = -0.0;
  w(6, 1) = 1e-310;  // subnormal
  const Eigen::MatrixXd mask =
      (RandomMatrix(4, 5, 8).array() > 0).cast<double>();
  const int num_points = 4, num_frames = 3;
  const Eigen::MatrixXd x = RandomMatrix(3, num_points * num_frames, 9);
  for (MatVersion version :
       {MatVersion::kV4, MatVersion::kV5, MatVersion::kV73}) {
    SCOPED_TRACE(static_cast<int>(version));
    const std::string path =
        dir + "/v" + std::to_string(static_cast<int>(version)) + ".mat";
    std::vector<MatVariable> variables = {{"W", w, {}}, {"mask", mask, {}}};
    if (version != MatVersion::kV4)
      variables.push_back({"X", x, {3, num_points, num_frames}});
    ASSERT_TRUE(WriteMat(path, version, variables).ok());

    std::vector<std::string> names;
    ASSERT_TRUE(ListMatVariables(path, &names).ok());
    std::vector<std::string> expected = {"W", "mask"};
    if (version == MatVersion::kV5) expected = {"W", "mask", "X"};
    if (version == MatVersion::kV73)
      expected = {"W", "X", "mask"};  // sorted by HDF5
    EXPECT_EQ(names, expected);

    Eigen::MatrixXd read;
    ASSERT_TRUE(ReadMatVariable(path, "W", &read).ok());
    EXPECT_TRUE(SameBits(read, w));
    EXPECT_TRUE(std::signbit(read(7, 0)));
    ASSERT_TRUE(ReadMatVariable(path, "mask", &read).ok());
    EXPECT_TRUE(SameBits(read, mask));
    // A 2-D variable is one slice of a 3-D array.
    std::vector<Eigen::MatrixXd> slices;
    ASSERT_TRUE(ReadMatArray3(path, "W", &slices).ok());
    ASSERT_EQ(slices.size(), 1u);
    EXPECT_TRUE(SameBits(slices[0], w));
    if (version == MatVersion::kV4) continue;
    ASSERT_TRUE(ReadMatArray3(path, "X", &slices).ok());
    ASSERT_EQ(static_cast<int>(slices.size()), num_frames);
    for (int t = 0; t < num_frames; ++t) {
      EXPECT_TRUE(SameBits(slices[t], x.middleCols(t * num_points, num_points)))
          << t;
    }
    // X(i, p, t) is element i + 3 (p + P t), as in MATLAB.
    EXPECT_EQ(slices[2](1, 3), x.data()[1 + 3 * (3 + num_points * 2)]);
    const Status s = ReadMatVariable(path, "X", &read);
    EXPECT_FALSE(s.ok());
    EXPECT_TRUE(Contains(s.message(), "'X' is 3-D (3 x 4 x 3)")) << s.message();
  }
}

TEST(MatIo, EmptyVariableReadsAsEmpty) {
  const std::string dir = MakeTempDir("mat_io_empty");
  for (MatVersion version :
       {MatVersion::kV4, MatVersion::kV5, MatVersion::kV73}) {
    SCOPED_TRACE(static_cast<int>(version));
    const std::string path =
        dir + "/e" + std::to_string(static_cast<int>(version)) + ".mat";
    ASSERT_TRUE(
        WriteMat(path, version, {{"E", Eigen::MatrixXd(0, 3), {}}}).ok());
    Eigen::MatrixXd read = Eigen::MatrixXd::Ones(2, 2);
    const Status s = ReadMatVariable(path, "E", &read);
    ASSERT_TRUE(s.ok()) << s.message();
    EXPECT_EQ(read.size(), 0);
  }
}

// Empty arrays of every shape, including the 3-D ones WriteMat cannot write
// from an empty matrix: a 2-D one reads as such, and ReadMatArray3 gives no
// slice for any of them (a 0 x 0 x 10^6 array is not a million matrices)
// but its size.
TEST(MatIo, EmptyArraysOfEveryShapeReadAsDocumented) {
  const std::string path = MakeTempDir("mat_io_empty_nd") + "/empty.mat";
  WriteBytes(path, Header() + Double("a_0x3", {0, 3}, {}) +
                       Double("a_4x0", {4, 0}, {}) +
                       Double("a_4x3x0", {4, 3, 0}, {}) +
                       Double("a_0x3x2", {0, 3, 2}, {}) +
                       Double("a_3x0x2", {3, 0, 2}, {}) +
                       Double("a_0x0x1000000", {0, 0, 1000000}, {}) +
                       Double("ok", {1, 1}, {7.0}));
  struct Case {
    std::string name;
    std::vector<std::size_t> dims;
    std::string dims_text;
  };
  for (const Case& c : std::vector<Case>{
           {"a_0x3", {0, 3, 1}, "0 x 3"},
           {"a_4x0", {4, 0, 1}, "4 x 0"},
           {"a_4x3x0", {4, 3, 0}, "4 x 3 x 0"},
           {"a_0x3x2", {0, 3, 2}, "0 x 3 x 2"},
           {"a_3x0x2", {3, 0, 2}, "3 x 0 x 2"},
           {"a_0x0x1000000", {0, 0, 1000000}, "0 x 0 x 1000000"}}) {
    SCOPED_TRACE(c.name);
    std::vector<Eigen::MatrixXd> slices(5, Eigen::MatrixXd::Ones(1, 1));
    std::vector<std::size_t> dims;
    const Status s = ReadMatArray3(path, c.name, &slices, &dims);
    ASSERT_TRUE(s.ok()) << s.message();
    EXPECT_TRUE(slices.empty());
    EXPECT_EQ(dims, c.dims);
    EXPECT_EQ(MatDimsString(dims), c.dims_text);
    Eigen::MatrixXd m = Eigen::MatrixXd::Ones(1, 1);
    if (c.dims[2] == 1) {
      ASSERT_TRUE(ReadMatVariable(path, c.name, &m).ok());
      EXPECT_EQ(m.rows(), static_cast<Eigen::Index>(c.dims[0]));
      EXPECT_EQ(m.cols(), static_cast<Eigen::Index>(c.dims[1]));
    } else {
      EXPECT_EQ(ReadMatVariable(path, c.name, &m).message(),
                path + ": variable '" + c.name + "' is 3-D (" + c.dims_text +
                    "); expected a 2-D matrix");
    }
  }
  std::vector<Eigen::MatrixXd> slices;
  std::vector<std::size_t> dims;
  ASSERT_TRUE(ReadMatArray3(path, "ok", &slices, &dims).ok());
  ASSERT_EQ(slices.size(), 1u);
  EXPECT_EQ(slices[0](0, 0), 7.0);
  EXPECT_EQ(dims, (std::vector<std::size_t>{1, 1, 1}));
}

// An empty array has no data to bound its other dimensions, so each one is
// bounded by the file size itself: a 0 x 2^31-1 x 2^31-1 array would
// otherwise ask for 2^31 slices.
TEST(MatIo, EmptyArrayWithAHugeDimensionIsRejected) {
  const std::string path = MakeTempDir("mat_io_empty_huge") + "/huge.mat";
  const int huge = 2147483647;
  WriteBytes(path, Header() + Double("W", {0, huge}, {}) +
                       Double("X", {0, huge, huge}, {}) +
                       Double("Y", {2, 3, huge}, {}));
  Eigen::MatrixXd m;
  Status s = ReadMatVariable(path, "W", &m);
  EXPECT_EQ(s.message(),
            path +
                ": variable 'W' claims a size of 0 x 2147483647, "
                "more than the file can hold (truncated or corrupt file?)");
  std::vector<Eigen::MatrixXd> slices;
  s = ReadMatArray3(path, "X", &slices);
  EXPECT_EQ(s.message(),
            path +
                ": variable 'X' claims a size of 0 x 2147483647 x 2147483647, "
                "more than the file can hold (truncated or corrupt file?)");
  s = ReadMatArray3(path, "Y", &slices);
  EXPECT_EQ(s.message(), path +
                             ": variable 'Y' claims a size of 2 x 3 x "
                             "2147483647, more than the file can hold "
                             "(truncated or corrupt file?)");
}

// Cells and structs, empty or holding empty fields, are listed and named in
// the error; the numeric variable after them still reads.
TEST(MatIo, EmptyCellsAndStructFieldsAreNamedNotRead) {
  const std::string path = MakeTempDir("mat_io_empty_cells") + "/cells.mat";
  WriteBytes(path,
             Header() + Cell("c0", {0, 0}, {}) +
                 Cell("c1", {1, 2}, {EmptyMatrix(), Double("", {0, 0}, {})}) +
                 Struct("st", {"empty", "zero"},
                        {EmptyMatrix(), Double("", {3, 0}, {})}) +
                 Double("ok", {1, 1}, {42.0}));
  std::vector<std::string> names;
  ASSERT_TRUE(ListMatVariables(path, &names).ok());
  EXPECT_EQ(names, (std::vector<std::string>{"c0", "c1", "st", "ok"}));
  for (const auto& [name, what] :
       std::vector<std::pair<std::string, std::string>>{{"c0", "a cell array"},
                                                        {"c1", "a cell array"},
                                                        {"st", "a struct"}}) {
    Eigen::MatrixXd m;
    EXPECT_EQ(ReadMatVariable(path, name, &m).message(),
              path + ": variable '" + name + "' is " + what +
                  ", not a numeric array");
    std::vector<Eigen::MatrixXd> slices;
    EXPECT_EQ(ReadMatArray3(path, name, &slices).message(),
              path + ": variable '" + name + "' is " + what +
                  ", not a numeric array");
  }
  Eigen::MatrixXd m;
  ASSERT_TRUE(ReadMatVariable(path, "ok", &m).ok());
  EXPECT_EQ(m(0, 0), 42.0);
}

// --- Numeric classes other than double (hand-made files).

TEST(MatIo, ReadsEveryNumericClassOfV4AsDouble) {
  const std::string path = MakeTempDir("mat_io_v4_classes") + "/classes.mat";
  WriteBytes(path,
             V4Variable("u8", 2, 2, 5, 0,
                        Raw(std::vector<std::uint8_t>{0, 250, 7, 13})) +
                 V4Variable("f", 1, 3, 1, 0,
                            Raw(std::vector<float>{1.5f, -0.25f, 1e30f})) +
                 V4Variable("i32", 1, 2, 2, 0,
                            Raw(std::vector<std::int32_t>{-70000, 8})) +
                 V4Variable("i16", 1, 2, 3, 0,
                            Raw(std::vector<std::int16_t>{-300, 301})) +
                 V4Variable("u16", 1, 1, 4, 0,
                            Raw(std::vector<std::uint16_t>{65535})));
  Eigen::MatrixXd m;
  ASSERT_TRUE(ReadMatVariable(path, "u8", &m).ok());
  EXPECT_EQ(m, (Eigen::MatrixXd(2, 2) << 0, 7, 250, 13).finished());
  ASSERT_TRUE(ReadMatVariable(path, "f", &m).ok());
  EXPECT_EQ(m, (Eigen::MatrixXd(1, 3) << 1.5, -0.25, static_cast<double>(1e30f))
                   .finished());
  ASSERT_TRUE(ReadMatVariable(path, "i32", &m).ok());
  EXPECT_EQ(m, (Eigen::MatrixXd(1, 2) << -70000, 8).finished());
  ASSERT_TRUE(ReadMatVariable(path, "i16", &m).ok());
  EXPECT_EQ(m, (Eigen::MatrixXd(1, 2) << -300, 301).finished());
  ASSERT_TRUE(ReadMatVariable(path, "u16", &m).ok());
  EXPECT_EQ(m(0, 0), 65535.0);
}

TEST(MatIo, ReadsEveryNumericClassOfV5AsDouble) {
  const std::string path = MakeTempDir("mat_io_v5_classes") + "/classes.mat";
  std::string file = Header();
  file += Matrix(kMxInt8, 0, {1, 2}, "i8",
                 Element(kMiInt8, Raw(std::vector<std::int8_t>{-128, 127})));
  file += Matrix(kMxUint8, 0, {1, 1}, "u8",
                 Element(kMiUint8, Raw(std::vector<std::uint8_t>{200})));
  file += Matrix(kMxInt16, 0, {1, 1}, "i16",
                 Element(kMiInt16, Raw(std::vector<std::int16_t>{-32768})));
  file += Matrix(kMxUint16, 0, {1, 1}, "u16",
                 Element(kMiUint16, Raw(std::vector<std::uint16_t>{40000})));
  file +=
      Matrix(kMxInt32, 0, {1, 1}, "i32",
             Element(kMiInt32, Raw(std::vector<std::int32_t>{-2000000000})));
  file +=
      Matrix(kMxUint32, 0, {1, 1}, "u32",
             Element(kMiUint32, Raw(std::vector<std::uint32_t>{4000000000u})));
  file +=
      Matrix(kMxInt64, 0, {1, 1}, "i64",
             Element(kMiInt64,
                     Raw(std::vector<std::int64_t>{-(std::int64_t(1) << 40)})));
  file +=
      Matrix(kMxUint64, 0, {1, 1}, "u64",
             Element(kMiUint64,
                     Raw(std::vector<std::uint64_t>{std::uint64_t(1) << 50})));
  file += Matrix(kMxSingle, 0, {1, 1}, "f",
                 Element(kMiSingle, Raw(std::vector<float>{-2.5f})));
  file += Matrix(kMxUint8, kFlagLogical, {2, 1}, "b",
                 Element(kMiUint8, Raw(std::vector<std::uint8_t>{1, 0})));
  // The trap: MATLAB stores integral doubles compactly, e.g. class double with
  // uint8 data (like K = 13 in drink.mat).
  file += Matrix(kMxDouble, 0, {1, 3}, "d_as_u8",
                 Element(kMiUint8, Raw(std::vector<std::uint8_t>{13, 0, 255})));
  // A 2 x 2 x 2 int16 array.
  file +=
      Matrix(kMxInt16, 0, {2, 2, 2}, "a3",
             Element(kMiInt16,
                     Raw(std::vector<std::int16_t>{1, 2, 3, 4, 5, 6, 7, 8})));
  WriteBytes(path, file);

  const std::vector<std::pair<std::string, double>> scalars = {
      {"u8", 200},
      {"i16", -32768},
      {"u16", 40000},
      {"i32", -2000000000},
      {"u32", 4000000000.0},
      {"i64", -1099511627776.0},
      {"u64", 1125899906842624.0},
      {"f", -2.5}};
  Eigen::MatrixXd m;
  for (const auto& [name, value] : scalars) {
    ASSERT_TRUE(ReadMatVariable(path, name, &m).ok()) << name;
    ASSERT_EQ(m.size(), 1) << name;
    EXPECT_EQ(m(0, 0), value) << name;
  }
  ASSERT_TRUE(ReadMatVariable(path, "i8", &m).ok());
  EXPECT_EQ(m, (Eigen::MatrixXd(1, 2) << -128, 127).finished());
  ASSERT_TRUE(ReadMatVariable(path, "b", &m).ok());
  EXPECT_EQ(m, (Eigen::MatrixXd(2, 1) << 1, 0).finished());
  ASSERT_TRUE(ReadMatVariable(path, "d_as_u8", &m).ok());
  EXPECT_EQ(m, (Eigen::MatrixXd(1, 3) << 13, 0, 255).finished());
  std::vector<Eigen::MatrixXd> slices;
  ASSERT_TRUE(ReadMatArray3(path, "a3", &slices).ok());
  ASSERT_EQ(slices.size(), 2u);
  EXPECT_EQ(slices[0], (Eigen::MatrixXd(2, 2) << 1, 3, 2, 4).finished());
  EXPECT_EQ(slices[1], (Eigen::MatrixXd(2, 2) << 5, 7, 6, 8).finished());
}

// --- Variables that are not real numeric matrices.

TEST(MatIo, RejectsNonNumericVariablesNamingThem) {
  const std::string dir = MakeTempDir("mat_io_non_numeric");
  const std::string v4 = dir + "/v4.mat";
  WriteBytes(
      v4,
      V4Variable("txt", 1, 2, 0, 1, Raw(std::vector<double>{72, 105})) +
          V4Variable("cplx", 1, 1, 0, 0, Raw(std::vector<double>{2.0}), true) +
          V4Variable("sp", 2, 3, 0, 2,
                     Raw(std::vector<double>{1, 2, 1, 1, 5, 6})));
  const std::string v5 = dir + "/v5.mat";
  const std::string field =
      Matrix(kMxDouble, 0, {1, 1}, "",
             Element(kMiDouble, Raw(std::vector<double>{1.0})));
  WriteBytes(
      v5, Header() +
              Matrix(kMxChar, 0, {1, 2}, "name",
                     Element(kMiUint16,
                             Raw(std::vector<std::uint16_t>{'h', 'i'}))) +
              Matrix(kMxStruct, 0, {1, 1}, "st",
                     Element(kMiInt32, Raw(std::vector<std::int32_t>{8})) +
                         Element(kMiInt8, std::string("a\0\0\0\0\0\0\0", 8)) +
                         field) +
              Matrix(kMxCell, 0, {1, 1}, "ce", field) +
              Matrix(kMxDouble, kFlagComplex, {1, 1}, "z",
                     Element(kMiDouble, Raw(std::vector<double>{1.0})) +
                         Element(kMiDouble, Raw(std::vector<double>{2.0}))) +
              Matrix(kMxSparse, 0, {2, 2}, "sp",
                     Element(kMiInt32, Raw(std::vector<std::int32_t>{1})) +
                         Element(kMiInt32,
                                 Raw(std::vector<std::int32_t>{0, 0, 1})) +
                         Element(kMiDouble, Raw(std::vector<double>{3.0})),
                     1) +
              Matrix(kMxDouble, 0, {1, 1}, "ok",
                     Element(kMiDouble, Raw(std::vector<double>{42.0}))));

  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {v4, "txt", "is a char array"},   {v4, "cplx", "is complex"},
      {v4, "sp", "is a sparse matrix"}, {v5, "name", "is a char array"},
      {v5, "st", "is a struct"},        {v5, "ce", "is a cell array"},
      {v5, "z", "is complex"},          {v5, "sp", "is a sparse matrix"}};
  for (const auto& [path, name, what] : cases) {
    Eigen::MatrixXd m;
    const Status s = ReadMatVariable(path, name, &m);
    EXPECT_FALSE(s.ok()) << name;
    EXPECT_TRUE(
        Contains(s.message(), path + ": variable '" + name + "' " + what))
        << s.message();
    std::vector<Eigen::MatrixXd> slices;
    EXPECT_FALSE(ReadMatArray3(path, name, &slices).ok()) << name;
  }
  // The numeric variable after all of them still reads.
  Eigen::MatrixXd m;
  ASSERT_TRUE(ReadMatVariable(v5, "ok", &m).ok());
  EXPECT_EQ(m(0, 0), 42.0);
  std::vector<std::string> names;
  ASSERT_TRUE(ListMatVariables(v5, &names).ok());
  EXPECT_EQ(names,
            (std::vector<std::string>{"name", "st", "ce", "z", "sp", "ok"}));
}

// --- Files that are not (complete) .mat files.

TEST(MatIo, BadFilesGiveClearErrorsAndNeverCrash) {
  const std::string dir = MakeTempDir("mat_io_bad_files");
  Eigen::MatrixXd m;
  std::vector<std::string> names;

  Status s = ReadMatVariable(dir + "/missing.mat", "W", &m);
  EXPECT_EQ(s.message(), dir + "/missing.mat: no such file");
  s = ListMatVariables(dir, &names);
  EXPECT_EQ(s.message(), dir + ": is a directory, not a .mat file");

  const std::string empty = dir + "/empty.mat";
  WriteBytes(empty, "");
  s = ReadMatVariable(empty, "W", &m);
  EXPECT_EQ(s.message(), empty + ": file is empty, not a .mat file");

  const std::string text = dir + "/text.mat";
  WriteBytes(text, "1 2 3\nthis is not a MATLAB file at all\n");
  s = ReadMatVariable(text, "W", &m);
  EXPECT_FALSE(s.ok());
  EXPECT_TRUE(Contains(s.message(), text + ": not a MATLAB .mat file"))
      << s.message();
  EXPECT_FALSE(ListMatVariables(text, &names).ok());

  // The first half of valid files of every version.
  const Eigen::MatrixXd w = RandomMatrix(60, 40, 3);
  for (MatVersion version :
       {MatVersion::kV4, MatVersion::kV5, MatVersion::kV73}) {
    SCOPED_TRACE(static_cast<int>(version));
    const std::string whole = dir + "/whole.mat";
    ASSERT_TRUE(WriteMat(whole, version, {{"W", w, {}}}).ok());
    const std::string bytes = ReadBytes(whole);
    const std::string half = dir + "/half.mat";
    WriteBytes(half, bytes.substr(0, bytes.size() / 2));
    s = ReadMatVariable(half, "W", &m);
    EXPECT_FALSE(s.ok());
    EXPECT_TRUE(Contains(s.message(), half + ": ")) << s.message();
    EXPECT_TRUE(Contains(s.message(), "truncated or corrupt")) << s.message();
    std::vector<Eigen::MatrixXd> slices;
    EXPECT_FALSE(ReadMatArray3(half, "W", &slices).ok());
    s = ListMatVariables(half, &names);
    EXPECT_TRUE(
        Contains(s.message(), half + ": the .mat file is truncated or corrupt"))
        << s.message();
  }
}

TEST(MatIo, HeaderClaimingMoreDataThanTheFileHoldsIsRejectedBeforeReading) {
  const std::string dir = MakeTempDir("mat_io_huge_dims");
  const std::string v4 = dir + "/v4.mat";
  WriteBytes(v4, V4Variable("W", 1 << 30, 1 << 30, 0, 0,
                            Raw(std::vector<double>{1, 2})));
  const std::string v5 = dir + "/v5.mat";
  WriteBytes(v5, Header() + Matrix(kMxDouble, 0, {100000, 100000}, "W",
                                   Element(kMiDouble,
                                           Raw(std::vector<double>{1, 2}))));
  Eigen::MatrixXd m;
  // v4: the data decide where the next record starts, so the whole file is
  // refused.
  EXPECT_EQ(ReadMatVariable(v4, "W", &m).message(),
            v4 + ": the .mat file is truncated or corrupt (variable 'W' claims "
                 "a size of "
                 "1073741824 x 1073741824, more than the 16 bytes after its "
                 "name hold)");
  EXPECT_EQ(ReadMatVariable(v5, "W", &m).message(),
            v5 + ": variable 'W' claims a size of 100000 x 100000, more than "
                 "the file can "
                 "hold (truncated or corrupt file?)");
}

// Every size a v5 file claims is bounded by the bytes that hold it before
// matio sees the file (core/io/mat_file_check.h): a 104-byte file whose name
// tag claims 4 GB made matio allocate and fill 4 GB (the fuzz corpus holds
// such a file). Claims inside a compressed variable are held to what its
// inflated bytes hold, and those to 1032 times the compressed bytes.
TEST(MatIo, ClaimsBeyondTheBytesThatHoldThemAreRejectedBeforeMatioSeesThem) {
  const std::string dir = MakeTempDir("mat_io_claims");
  const std::string flags =
      Element(kMiUint32, Raw(std::vector<std::uint32_t>{kMxDouble, 0}));
  const std::string dims =
      Element(kMiInt32, Raw(std::vector<std::int32_t>{2, 2}));
  const std::string data =
      Element(kMiDouble, Raw(std::vector<double>{1, 2, 3, 4}));
  // A name tag (miINT8) that claims 0xfc000001 bytes, then 8 name bytes.
  const std::string huge_name =
      Raw(std::vector<std::uint32_t>{kMiInt8, 0xfc000001u}) +
      std::string("W\0\0\0\0\0\0\0", 8);
  const std::string prefix = ": the .mat file is truncated or corrupt (";
  struct Case {
    std::string file, bytes, message;
  };
  const std::vector<Case> cases = {
      {"name.mat",
       Header() + Element(kMiMatrix, flags + dims + huge_name + data),
       "variable 1 at byte 128: a data element claims 4227858433 bytes, more "
       "than the 48 left "
       "in its array)"},
      {"zname.mat",
       Header() +
           Compressed(Element(kMiMatrix, flags + dims + huge_name + data)),
       "variable 1 at byte 128 (compressed): a data element claims 4227858433 "
       "bytes, more than "
       "the 48 left in its array)"},
      {"dims.mat",
       Header() +
           Element(kMiMatrix,
                   flags + Raw(std::vector<std::uint32_t>{kMiInt32, 1u << 30}) +
                       Raw(std::vector<std::int32_t>{2, 2}) + data),
       "variable 1 at byte 128: a data element claims 1073741824 bytes, more "
       "than the 48 left in "
       "its array)"},
      {"inflated.mat",
       Header() + Compressed(Double("W", {2, 2}, {1, 2, 3, 4}), 1 << 30),
       "variable 1 at byte 128 (compressed): it claims 1073741824 bytes "
       "inflated from "},
      {"cells.mat", Header() + Compressed(Cell("c", {2048, 2048}, {})),
       "variable 'c': it claims 4194304 cells, more than its 0 bytes can "
       "hold)"},
      {"fields.mat",
       Header() +
           Matrix(kMxStruct, 0, {1000, 1000}, "s",
                  Raw(std::vector<std::uint32_t>{(4u << 16) | kMiInt32, 8}) +
                      Element(kMiInt8,
                              std::string("ab\0\0\0\0\0\0cd\0\0\0\0\0\0", 16))),
       "variable 's': it claims 2000000 fields, more than its 0 bytes can "
       "hold)"},
      {"truncated.mat",
       Header() + Double("W", {2, 2}, {1, 2, 3, 4}).substr(0, 40),
       "variable 1 at byte 128: it claims 88 bytes, more than the 32 left in "
       "the file)"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    const std::string path = dir + "/" + c.file;
    WriteBytes(path, c.bytes);
    std::vector<std::string> names;
    const Status listed = ListMatVariables(path, &names);
    EXPECT_TRUE(Contains(listed.message(), path + prefix + c.message))
        << listed.message();
    Eigen::MatrixXd m;
    EXPECT_EQ(ReadMatVariable(path, "W", &m).message(), listed.message());
  }

  // Arrays nested 70 deep (matio reads them recursively).
  std::string nested = Double("", {1, 1}, {1.0});
  for (int depth = 0; depth < 70; ++depth)
    nested = Cell(depth == 69 ? "deep" : "", {1, 1}, {nested});
  const std::string deep = dir + "/deep.mat";
  WriteBytes(deep, Header() + nested);
  std::vector<std::string> names;
  EXPECT_TRUE(Contains(ListMatVariables(deep, &names).message(),
                       "(variable 'deep' element 1 element 1"))
      << ListMatVariables(deep, &names).message();
  EXPECT_TRUE(Contains(ListMatVariables(deep, &names).message(),
                       ": arrays nested more than 64 deep)"));
}

// An opaque object (how MATLAB stores a string, a table, …) has no
// dimensions element: the check passes over it, and the variables after it
// read.
TEST(MatIo, OpaqueObjectsDoNotStopTheCheck) {
  const std::string path = MakeTempDir("mat_io_opaque") + "/opaque.mat";
  const std::string opaque = Element(
      kMiMatrix, Element(kMiUint32, Raw(std::vector<std::uint32_t>{17, 0})) +
                     Element(kMiInt8, "s") + Element(kMiInt8, "MCOS") +
                     Element(kMiInt8, "string") + Double("", {1, 1}, {0.0}));
  WriteBytes(path, Header() + opaque + Double("ok", {1, 1}, {4.0}));
  std::vector<std::string> names;
  ASSERT_TRUE(ListMatVariables(path, &names).ok());
  Eigen::MatrixXd m;
  ASSERT_TRUE(ReadMatVariable(path, "ok", &m).ok());
  EXPECT_EQ(m(0, 0), 4.0);
}

// A numeric variable whose data hold fewer elements than its dimensions
// claim is refused when it is read, naming it; the file's other variables
// still read (compressed and not).
TEST(MatIo, VariableWhoseDataHoldLessThanItsSizeIsRefusedAlone) {
  const std::string dir = MakeTempDir("mat_io_short_data");
  const std::string ok = Double("ok", {1, 2}, {5.0, 6.0});
  const std::string short_w = Double("W", {100, 100}, {1.0, 2.0});
  for (const auto& [file, bytes] :
       std::vector<std::pair<std::string, std::string>>{
           {"plain.mat", Header() + short_w + ok},
           {"zlib.mat", Header() + Compressed(short_w) + Compressed(ok)}}) {
    SCOPED_TRACE(file);
    const std::string path = dir + "/" + file;
    WriteBytes(path, bytes);
    Eigen::MatrixXd m;
    EXPECT_EQ(ReadMatVariable(path, "W", &m).message(),
              path +
                  ": variable 'W' claims a size of 100 x 100, more than the "
                  "file can hold "
                  "(truncated or corrupt file?)");
    ASSERT_TRUE(ReadMatVariable(path, "ok", &m).ok());
    EXPECT_EQ(m, (Eigen::MatrixXd(1, 2) << 5.0, 6.0).finished());
    std::vector<std::string> names;
    ASSERT_TRUE(ListMatVariables(path, &names).ok());
    EXPECT_EQ(names, (std::vector<std::string>{"W", "ok"}));
  }
}

// v4: matio takes the byte order of a record from the thousands digit of
// its type (0 little-endian, 1 big-endian), whatever order the type itself
// was stored in. A 29-byte file whose type reads 1 only byte-swapped is
// little-endian for matio, so its name length is 0x09000000 (matio
// allocated and read 150 MB for it); a real big-endian file (type 1000)
// reads.
TEST(MatIo, V4ByteOrderIsReadAsMatioReadsIt) {
  const std::string dir = MakeTempDir("mat_io_v4_order");
  const std::string swapped = dir + "/swapped.mat";
  WriteBytes(swapped,
             Raw(std::vector<std::uint8_t>{0, 0,    0, 1, 0, 0, 1, 0, 0, 0,
                                           0, 0x58, 0, 0, 0, 0, 0, 0, 0, 9}) +
                 "W\0\0\0\0\0\0\0\0");
  Eigen::MatrixXd m;
  EXPECT_EQ(ReadMatVariable(swapped, "W", &m).message(),
            swapped +
                ": the .mat file is truncated or corrupt (the name of variable "
                "1 of a v4 "
                "file at byte 0 runs past the end of the file)");

  const std::string big = dir + "/big.mat";
  std::string bytes;
  for (std::int32_t field : {1000, 1, 2, 0, 2}) {
    for (int shift = 24; shift >= 0; shift -= 8)
      bytes += static_cast<char>(field >> shift);
  }
  bytes += std::string("W\0", 2);
  for (double value : {1.5, -2.0}) {
    const std::string raw = Raw(std::vector<double>{value});
    bytes += std::string(raw.rbegin(), raw.rend());
  }
  WriteBytes(big, bytes);
  ASSERT_TRUE(ReadMatVariable(big, "W", &m).ok())
      << ReadMatVariable(big, "W", &m).message();
  EXPECT_EQ(m, (Eigen::MatrixXd(1, 2) << 1.5, -2.0).finished());
}

TEST(MatIo, RandomlyCorruptedFilesNeverCrash) {
  // Seeded byte corruption of small v4 and v5 files: every call returns
  // (OK with some values, or an error naming the file).
  const std::string dir = MakeTempDir("mat_io_corrupt");
  const std::vector<MatVariable> variables = {
      {"W", RandomMatrix(6, 5, 1), {}},
      {"mask", Eigen::MatrixXd::Ones(3, 5), {}}};
  std::mt19937 rng(5);
  for (MatVersion version : {MatVersion::kV4, MatVersion::kV5}) {
    const std::string whole = dir + "/whole.mat";
    ASSERT_TRUE(WriteMat(whole, version, variables).ok());
    const std::string bytes = ReadBytes(whole);
    const std::string path = dir + "/corrupt.mat";
    int errors = 0;
    for (int trial = 0; trial < 150; ++trial) {
      std::string corrupt = bytes;
      const int flips = 1 + static_cast<int>(rng() % 4);
      for (int k = 0; k < flips; ++k)
        corrupt[rng() % corrupt.size()] = static_cast<char>(rng());
      WriteBytes(path, corrupt);
      Eigen::MatrixXd m;
      std::vector<std::string> names;
      const Status s = ReadMatVariable(path, "W", &m);
      if (!s.ok()) {
        ++errors;
        EXPECT_TRUE(Contains(s.message(), path + ":")) << s.message();
      }
      ListMatVariables(path, &names);
    }
    EXPECT_GT(errors, 0);
  }
}

TEST(MatIo, MissingVariableListsTheVariablesThatExist) {
  const std::string path = MakeTempDir("mat_io_missing_var") + "/two.mat";
  ASSERT_TRUE(WriteMat(path, MatVersion::kV73,
                       {{"alpha", Eigen::MatrixXd::Ones(2, 2), {}},
                        {"beta", Eigen::MatrixXd::Zero(1, 1), {}}})
                  .ok());
  Eigen::MatrixXd m;
  const Status s = ReadMatVariable(path, "W", &m);
  EXPECT_EQ(s.message(), path + ": no variable 'W'; the file has: alpha, beta");
  EXPECT_FALSE(ReadMatVariable(path, "", &m).ok());
}

TEST(MatIo, WriteMatRejectsBadRequests) {
  const std::string dir = MakeTempDir("mat_io_write_errors");
  const Eigen::MatrixXd m = Eigen::MatrixXd::Ones(2, 6);
  const std::string path = dir + "/out.mat";
  Status s = WriteMat(path, MatVersion::kV5, {{"1abc", m, {}}});
  EXPECT_TRUE(Contains(s.message(), "'1abc' is not a valid MATLAB name"))
      << s.message();
  s = WriteMat(path, MatVersion::kV5, {{"a", m, {}}, {"a", m, {}}});
  EXPECT_TRUE(Contains(s.message(), "'a' is given twice")) << s.message();
  s = WriteMat(path, MatVersion::kV5, {{"a", m, {2, 2, 2}}});
  EXPECT_TRUE(
      Contains(s.message(),
               "product of dims (8) differs from the number of values (12)"))
      << s.message();
  s = WriteMat(path, MatVersion::kV4, {{"a", m, {2, 3, 2}}});
  EXPECT_TRUE(Contains(s.message(), "v4 files cannot hold N-D arrays"))
      << s.message();
  EXPECT_FALSE(std::filesystem::exists(path));
  for (MatVersion version :
       {MatVersion::kV4, MatVersion::kV5, MatVersion::kV73}) {
    s = WriteMat(dir + "/no/such/dir/out.mat", version, {{"a", m, {}}});
    EXPECT_TRUE(Contains(
        s.message(), dir + "/no/such/dir/out.mat: cannot create the .mat file"))
        << s.message();
  }
}

// --- The real datasets.

TEST(MatIo, ReadsTheRealDatasets) {
  NRSFM_SKIP_WITHOUT_SHARED_DATA(dir);
  std::vector<std::string> names;
  ASSERT_TRUE(ListMatVariables(dir + "/drink.mat", &names).ok());
  EXPECT_EQ(names,
            (std::vector<std::string>{"K", "Rs", "S", "Shat", "W", "filename",
                                      "list", "scale", "theta"}));
  Eigen::MatrixXd m;
  ASSERT_TRUE(
      ReadMatVariable(dir + "/drink.mat", "K", &m).ok());  // stored as uint8
  EXPECT_EQ(m(0, 0), 13.0);
  ASSERT_TRUE(ReadMatVariable(dir + "/drink.mat", "W", &m).ok());
  EXPECT_EQ(m.rows(), 2204);
  EXPECT_EQ(m.cols(), 41);
  const Status s = ReadMatVariable(dir + "/drink.mat", "filename", &m);
  EXPECT_TRUE(Contains(s.message(), "'filename' is a char array"))
      << s.message();

  ASSERT_TRUE(ReadMatVariable(dir + "/face.mat", "P3_gt", &m).ok());  // v4
  EXPECT_EQ(m.rows(), 948);
  EXPECT_EQ(m.cols(), 40);
  EXPECT_TRUE(m.allFinite());
  for (const char* name : {"pickup.mat", "yoga.mat"}) {
    ASSERT_TRUE(ReadMatVariable(dir + "/" + name, "W", &m).ok()) << name;
    EXPECT_EQ(m.cols(), 41) << name;
  }
}

}  // namespace
}  // namespace nrsfm
