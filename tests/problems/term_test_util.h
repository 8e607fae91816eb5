// Helpers shared by the tests of the extra terms (problems/extra_terms.h):
// tests/problems/extra_terms_test.cc checks every row of ExtraTerms() alike,
// and each term's own test (tests/problems/<term>_error_test.cc) checks how
// many residual blocks its row adds, on the same small sequence.
#ifndef NRSFM_TESTS_PROBLEMS_TERM_TEST_UTIL_H_
#define NRSFM_TESTS_PROBLEMS_TERM_TEST_UTIL_H_

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "core/synthetic/synthetic.h"
#include "problems/extra_terms.h"
#include "problems/problem_builder.h"
#include "problems/problem_options.h"

namespace nrsfm {
namespace testing_util {

// The sequence of the term tests: a shoe of F = 6 frames and P = 12 points,
// every point seen in every frame, seen by `cameras` synchronised cameras.
constexpr int kTermFrames = 6;
constexpr int kTermPoints = 12;

inline SyntheticSequence TermTestShoe(int cameras) {
  ShoeOptions options;
  options.num_frames = kTermFrames;
  options.num_points = kTermPoints;
  options.num_cameras = cameras;
  options.self_occlusion = false;
  options.noise_stddev = 0.01;
  SyntheticSequence sequence;
  EXPECT_TRUE(GenerateShoe(options, &sequence).ok());
  return sequence;
}

// The residual blocks AddExtraTerms adds per row of ExtraTerms() (aligned
// with it) with the weights `weights`, on the truth of `sequence`; -1 each
// when adding fails.
inline std::vector<int> TermBlockCounts(
    const std::map<std::string, double>& weights,
    const SyntheticSequence& sequence) {
  ProblemOptions options;
  options.term_weights = weights;
  Measurements measurements = sequence.measurements;
  Model model = sequence.truth;
  ProblemBuilder builder(&measurements, &model);
  std::vector<int> counts(ExtraTerms().size(), -1);
  if (!builder.AddReprojectionTerms(options).ok()) return counts;
  const Status status = AddExtraTerms(options, &builder, &counts);
  EXPECT_TRUE(status.ok()) << status.message();
  return counts;
}

// The residual blocks the term `name` alone (λ = 2) adds on `sequence`.
inline int TermBlockCount(const std::string& name,
                          const SyntheticSequence& sequence) {
  const ExtraTerm* term = FindExtraTerm(name);
  EXPECT_NE(term, nullptr) << name;
  if (term == nullptr) return -1;
  return TermBlockCounts({{name, 2.0}}, sequence)[term - ExtraTerms().data()];
}

}  // namespace testing_util
}  // namespace nrsfm

#endif  // NRSFM_TESTS_PROBLEMS_TERM_TEST_UTIL_H_
