// Helpers shared by the tests of Refine() (refine_test.cc;
// refine_progress_test.cc: its summary, progress reports and stop
// requests): seeded random-basis sequences and a perturbed start.
#ifndef NRSFM_TESTS_SOLVERS_REFINE_REFINE_TEST_UTIL_H_
#define NRSFM_TESTS_SOLVERS_REFINE_REFINE_TEST_UTIL_H_

#include <Eigen/Core>
#include <cstdint>
#include <random>

#include "core/model/model.h"
#include "core/synthetic/synthetic.h"
#include "tests/synthetic_sequences.h"

namespace nrsfm {
namespace testing_util {

inline SyntheticSequence Sequence(int frames, int points, int bases,
                                  double noise, double missing = 0.0,
                                  std::uint64_t seed = 5) {
  return RandomBasisSequence(frames, points, bases, noise, missing, seed);
}

// Adds N(0, sigma²) to every rotation, weight and basis entry.
inline Model Perturbed(const Model& model, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, sigma);
  Model out = model;
  auto perturb = [&](auto& matrix) {
    for (Eigen::Index i = 0; i < matrix.size(); ++i)
      matrix.data()[i] += normal(rng);
  };
  perturb(out.rotations);
  perturb(out.weights);
  perturb(out.basis);
  return out;
}

}  // namespace testing_util
}  // namespace nrsfm

#endif  // NRSFM_TESTS_SOLVERS_REFINE_REFINE_TEST_UTIL_H_
