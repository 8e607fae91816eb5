// Hand-computed residuals and Jacobian checks of problems/smoothness_error.h.
#include "problems/smoothness_error.h"

#include <ceres/gradient_checker.h>
#include <ceres/numeric_diff_options.h>
#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <vector>

#include "problems/delaunay_edges.h"
#include "tests/problems/functor_test_util.h"
#include "tests/problems/term_test_util.h"

namespace nrsfm {
namespace {

using testing_util::ExpectGradientCheckPasses;
using testing_util::Random;

TEST(SmoothnessError, HandComputedResidual) {
  const int k = 2;
  const double b_i[6] = {1, 2, 3, 4, 5, 6};
  const double b_j[6] = {0.5, 2, 4, 4, 3, 7};
  std::unique_ptr<ceres::CostFunction> cost(
      SmoothnessError::Create(k, 3.0, 0.5));
  EXPECT_EQ(cost->num_residuals(), 6);
  ASSERT_EQ(cost->parameter_block_sizes(), (std::vector<int32_t>{6, 6}));
  const double* parameters[2] = {b_i, b_j};
  double r[6];
  ASSERT_TRUE(cost->Evaluate(parameters, r, nullptr));
  // sqrt(λ) α (b_i − b_j) = 1.5 · (0.5, 0, −1, 0, 2, −1).
  const double expected[6] = {0.75, 0.0, -1.5, 0.0, 3.0, -1.5};
  for (int i = 0; i < 6; ++i) EXPECT_DOUBLE_EQ(r[i], expected[i]) << i;
}

TEST(SmoothnessError, GradientChecker) {
  std::mt19937 rng(3);
  for (const int k : {1, 3, 7}) {
    std::unique_ptr<ceres::CostFunction> cost(
        SmoothnessError::Create(k, 0.7, 1.3));
    const std::vector<double> b_i = Random(3 * k, &rng);
    const std::vector<double> b_j = Random(3 * k, &rng);
    ExpectGradientCheckPasses(*cost, {b_i.data(), b_j.data()});
  }
}

// Its row of problems/extra_terms.cc: one block per Delaunay neighbour edge.
TEST(SmoothnessTerm, OneBlockPerNeighbourEdge) {
  const SyntheticSequence s = testing_util::TermTestShoe(1);
  std::vector<NeighbourEdge> edges;
  ASSERT_TRUE(
      ComputeDelaunayEdges(s.measurements, DelaunayEdgesOptions(), &edges)
          .ok());
  EXPECT_GT(static_cast<int>(edges.size()),
            testing_util::kTermPoints);  // a triangulation
  EXPECT_EQ(testing_util::TermBlockCount(kSmoothnessTerm, s),
            static_cast<int>(edges.size()));
}

}  // namespace
}  // namespace nrsfm
