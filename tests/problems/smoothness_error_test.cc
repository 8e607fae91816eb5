// Hand-computed residuals and Jacobian checks of problems/smoothness_error.h.
#include "problems/smoothness_error.h"

#include <ceres/gradient_checker.h>
#include <ceres/numeric_diff_options.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/LU>
#include <memory>
#include <random>
#include <vector>

#include "problems/delaunay_edges.h"
#include "tests/problems/functor_test_util.h"
#include "tests/problems/jacobian_product_test_util.h"
#include "tests/problems/term_test_util.h"

namespace nrsfm {
namespace {

using testing_util::ExpectGradientCheckPasses;
using testing_util::Random;

TEST(SmoothnessError, HandComputedResidualAndJacobian) {
  const int k = 2;
  const double l[2] = {2.0, -1.0};
  const double b_i[6] = {1, 2, 3, 4, 5, 6};
  const double b_j[6] = {0.5, 2, 4, 4, 3, 7};
  std::unique_ptr<ceres::CostFunction> cost(
      SmoothnessError::Create(k, 3.0, 0.5));
  EXPECT_EQ(cost->num_residuals(), 3);
  ASSERT_EQ(cost->parameter_block_sizes(), (std::vector<int32_t>{2, 6, 6}));
  const double* parameters[3] = {l, b_i, b_j};
  double r[3], j_l[6], j_i[18], j_j[18];
  double* jacobians[3] = {j_l, j_i, j_j};
  ASSERT_TRUE(cost->Evaluate(parameters, r, jacobians));
  // b_i − b_j = (0.5, 0, −1 | 0, 2, −1); the frame's shape difference
  // 2 (0.5, 0, −1) − (0, 2, −1) = (1, −2, −1), times s = 3 · 0.5.
  const double expected[3] = {1.5, -3.0, -1.5};
  for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(r[i], expected[i]) << i;
  // ∂r/∂l_k = s (b_i,k − b_j,k): row c, column k.
  const double expected_l[6] = {0.75, 0.0, 0.0, 3.0, -1.5, -1.5};
  for (int i = 0; i < 6; ++i) EXPECT_DOUBLE_EQ(j_l[i], expected_l[i]) << i;
  // ∂r/∂b_i = s [l_1 I, l_2 I] = −∂r/∂b_j.
  for (int c = 0; c < 3; ++c) {
    for (int col = 0; col < 6; ++col) {
      const double want = col % 3 == c ? 1.5 * l[col / 3] : 0.0;
      EXPECT_DOUBLE_EQ(j_i[6 * c + col], want);
      EXPECT_DOUBLE_EQ(j_j[6 * c + col], -want);
    }
  }
}

TEST(SmoothnessError, GradientChecker) {
  std::mt19937 rng(3);
  for (const int k : {1, 3, 7}) {
    std::unique_ptr<ceres::CostFunction> cost(
        SmoothnessError::Create(k, 0.7, 1.3));
    const std::vector<double> l = Random(k, &rng);
    const std::vector<double> b_i = Random(3 * k, &rng);
    const std::vector<double> b_j = Random(3 * k, &rng);
    ExpectGradientCheckPasses(*cost, {l.data(), b_i.data(), b_j.data()});
  }
}

TEST(SmoothnessError, ProductsAndBilinearFormAreThoseOfTheJacobian) {
  // J x and Jᵀ y formed from the parameters (problems/jacobian_product.h)
  // against the Jacobian Evaluate() returns; the form
  // r = s · (B_i − B_j) l_t.
  std::mt19937 rng(5);
  for (int k : {1, 3, 7}) {
    SmoothnessError cost(k, 0.8);
    EXPECT_FALSE(cost.ProvidesGram());
    testing_util::ExpectProductsEqualTheJacobian(cost, cost, &rng);
    testing_util::ExpectTheBilinearFormGivesTheResidual(cost, cost, &rng);
  }
}

TEST(SmoothnessError, InvariantToTheGauge) {
  // Basis Q B and weights L Q⁻¹ give the same shapes, hence the same
  // residual (the basis-only form shrank the basis to lower its cost).
  const int k = 2;
  const double l[2] = {0.3, 1.7};
  const double b_i[6] = {1, 2, 3, 4, 5, 6};
  const double b_j[6] = {0.5, 2, 4, 4, 3, 7};
  Eigen::Matrix2d q;
  q << 0.2, 0.5, -0.1, 0.3;
  const Eigen::Matrix2d q_inverse = q.inverse();
  double l2[2], bi2[6], bj2[6];
  for (int a = 0; a < 2; ++a) {
    l2[a] = l[0] * q_inverse(0, a) + l[1] * q_inverse(1, a);
    for (int c = 0; c < 3; ++c) {
      bi2[3 * a + c] = q(a, 0) * b_i[c] + q(a, 1) * b_i[3 + c];
      bj2[3 * a + c] = q(a, 0) * b_j[c] + q(a, 1) * b_j[3 + c];
    }
  }
  std::unique_ptr<ceres::CostFunction> cost(
      SmoothnessError::Create(k, 1.0, 1.0));
  const double* before[3] = {l, b_i, b_j};
  const double* after[3] = {l2, bi2, bj2};
  double r[3], r2[3];
  ASSERT_TRUE(cost->Evaluate(before, r, nullptr));
  ASSERT_TRUE(cost->Evaluate(after, r2, nullptr));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r2[i], r[i], 1e-12) << i;
}

// Its row of problems/extra_terms.cc: one block per frame and Delaunay
// neighbour edge.
TEST(SmoothnessTerm, OneBlockPerFrameAndNeighbourEdge) {
  const SyntheticSequence s = testing_util::TermTestShoe(1);
  std::vector<NeighbourEdge> edges;
  ASSERT_TRUE(
      ComputeDelaunayEdges(s.measurements, DelaunayEdgesOptions(), &edges)
          .ok());
  EXPECT_GT(static_cast<int>(edges.size()),
            testing_util::kTermPoints);  // a triangulation
  EXPECT_EQ(testing_util::TermBlockCount(kSmoothnessTerm, s),
            s.truth.num_frames * static_cast<int>(edges.size()));
}

}  // namespace
}  // namespace nrsfm
