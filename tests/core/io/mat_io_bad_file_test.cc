// core/io/mat_io.h on files it must refuse, with a clear error and never a
// crash: files that are not (complete) .mat files, sizes claimed beyond the
// bytes that hold them, byte order, random corruption.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/io/mat_io.h"
#include "tests/core/io/mat_io_test_util.h"
#include "tests/mat_v5_bytes.h"
#include "tests/test_util.h"

namespace nrsfm {
namespace {

using testing_util::Contains;
using testing_util::MakeTempDir;
using testing_util::RandomMatrix;
using testing_util::ReadBytes;
using testing_util::V4Variable;
using testing_util::WriteBytes;
// Hand-made v5 files: tests/mat_v5_bytes.h (Header, Element, Matrix, kMi*,
// kMx*).
using namespace testing_util::v5;

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

}  // namespace
}  // namespace nrsfm
