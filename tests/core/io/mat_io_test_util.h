// Helpers shared by the tests of core/io/mat_io.h (mat_io_test.cc: files
// that read; mat_io_bad_file_test.cc: files that must be refused): byte
// files on disk, random and bit-identical matrices, and hand-made v4
// variables (v5 ones: tests/mat_v5_bytes.h).
#ifndef NRSFM_TESTS_CORE_IO_MAT_IO_TEST_UTIL_H_
#define NRSFM_TESTS_CORE_IO_MAT_IO_TEST_UTIL_H_

#include <Eigen/Core>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "tests/mat_v5_bytes.h"

namespace nrsfm {
namespace testing_util {

inline bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Bit-identical, NaN included.
inline bool SameBits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         (a.size() ==
              0 ||  // memcmp must not see an empty matrix's null pointer
          std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0);
}

inline Eigen::MatrixXd RandomMatrix(int rows, int cols, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 100.0);
  Eigen::MatrixXd m(rows, cols);
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = normal(rng);
  return m;
}

inline void WriteBytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// A hand-made MATLAB v4 variable (little endian), for classes WriteMat
// cannot write: 5 int32 (MOPT, rows, cols, imagf, name length), name, data.
inline std::string V4Variable(const std::string& name, int rows, int cols,
                              int precision, int type, const std::string& data,
                              bool complex = false) {
  const std::vector<std::int32_t> header = {
      precision * 10 + type, rows, cols, complex ? 1 : 0,
      static_cast<std::int32_t>(name.size() + 1)};
  return v5::Raw(header) + name + std::string(1, '\0') + data +
         (complex ? data : "");
}

}  // namespace testing_util
}  // namespace nrsfm

#endif  // NRSFM_TESTS_CORE_IO_MAT_IO_TEST_UTIL_H_
