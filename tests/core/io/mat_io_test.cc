#include "core/io/mat_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <tuple>
#include <vector>

#include "tests/core/io/mat_io_test_util.h"
#include "tests/mat_v5_bytes.h"
#include "tests/test_util.h"

namespace nrsfm {
namespace {

using testing_util::Contains;
using testing_util::MakeTempDir;
using testing_util::RandomMatrix;
using testing_util::SameBits;
using testing_util::V4Variable;
using testing_util::WriteBytes;
// Hand-made v5 files: tests/mat_v5_bytes.h (Header, Element, Matrix, kMi*,
// kMx*).
using namespace testing_util::v5;

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
