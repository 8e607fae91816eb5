// Helpers shared by the residual-functor tests.
#ifndef NRSFM_TESTS_PROBLEMS_FUNCTOR_TEST_UTIL_H_
#define NRSFM_TESTS_PROBLEMS_FUNCTOR_TEST_UTIL_H_

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace nrsfm {
namespace testing_util {

// ceres::GradientChecker on Euclidean parameters at `parameters`.
inline void ExpectGradientCheckPasses(
    const ceres::CostFunction& cost,
    const std::vector<const double*>& parameters) {
  ceres::NumericDiffOptions numeric_options;
  const std::vector<const ceres::Manifold*>* euclidean = nullptr;
  ceres::GradientChecker checker(&cost, euclidean, numeric_options);
  ceres::GradientChecker::ProbeResults results;
  EXPECT_TRUE(checker.Probe(parameters.data(), 1e-7, &results))
      << results.error_log;
}

// n values uniform in [-1, 1].
inline std::vector<double> Random(int n, std::mt19937* rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<double> v(n);
  for (double& x : v) x = uniform(*rng);
  return v;
}

}  // namespace testing_util
}  // namespace nrsfm

#endif  // NRSFM_TESTS_PROBLEMS_FUNCTOR_TEST_UTIL_H_
