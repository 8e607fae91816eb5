// Helpers shared by the tests of core/synthetic/synthetic.h
// (synthetic_test.cc: the random-basis, superquadric and shoe generators;
// synthetic_reproject_test.cc: re-projected ground truth).
#ifndef NRSFM_TESTS_CORE_SYNTHETIC_SYNTHETIC_TEST_UTIL_H_
#define NRSFM_TESTS_CORE_SYNTHETIC_SYNTHETIC_TEST_UTIL_H_

#include <Eigen/Core>
#include <cstring>

#include "core/model/measurements.h"

namespace nrsfm {
namespace testing_util {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;

inline bool SameBytes(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  // memcmp must not see the null data pointer of an empty matrix.
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         (a.size() == 0 ||
          std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0);
}

inline double MissingFraction(const Measurements& m, int camera) {
  int visible = 0;
  for (int t = 0; t < m.num_frames; ++t)
    visible += m.visible.row(m.View(t, camera)).count();
  return 1.0 - static_cast<double>(visible) / (m.num_frames * m.num_points);
}

}  // namespace testing_util
}  // namespace nrsfm

#endif  // NRSFM_TESTS_CORE_SYNTHETIC_SYNTHETIC_TEST_UTIL_H_
