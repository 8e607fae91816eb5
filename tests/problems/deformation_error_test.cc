// The deformation prior (problems/deformation_error.h): hand-computed
// residuals, the Jacobian against numeric differentiation, and what it does
// not penalise (basis shape 1 at any scale, the relative scale of weights and
// basis).
#include "problems/deformation_error.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "tests/problems/functor_test_util.h"
#include "tests/problems/jacobian_product_test_util.h"
#include "tests/problems/term_test_util.h"

namespace nrsfm {
namespace {

using testing_util::ExpectGradientCheckPasses;
using testing_util::Random;

TEST(DeformationError, HandComputedResidualAndGradient) {
  // K = 3; point p of basis 1 = (1, 2, 3), of basis 2 = (0, −1, 4), of
  // basis 3 = (2, 0, 1).
  const double basis[9] = {1.0, 2.0, 3.0, 0.0, -1.0, 4.0, 2.0, 0.0, 1.0};
  const double weights[3] = {7.0, 0.5, -1.0};
  DeformationError cost(3, 2.0);
  const double* parameters[2] = {weights, basis};
  double r[3];
  ASSERT_TRUE(cost.Evaluate(parameters, r, nullptr));
  // 2 · (0.5 · (0, −1, 4) − 1 · (2, 0, 1)) = (−4, −1, 2); basis 1 not counted.
  EXPECT_DOUBLE_EQ(r[0], -4.0);
  EXPECT_DOUBLE_EQ(r[1], -1.0);
  EXPECT_DOUBLE_EQ(r[2], 2.0);
  ExpectGradientCheckPasses(cost, {weights, basis});
  std::mt19937 rng(21);
  for (int k : {1, 2, 5, 12}) {
    DeformationError random_cost(k, 0.7);
    const std::vector<double> v = Random(4 * k, &rng);
    ExpectGradientCheckPasses(random_cost, {v.data(), v.data() + k});
  }
}

TEST(DeformationError, ZeroForAnyMultipleOfTheFirstShapeAndKeepsTheScaleGauge) {
  const double basis[6] = {1.0, 2.0, 3.0, 0.5, -1.0, 4.0};
  DeformationError cost(2, 1.0);
  double r[3];
  // A frame that is basis shape 1 at any scale (the camera's scale) costs 0.
  for (double scale : {1.0, 0.3, -2.0}) {
    const double weights[2] = {scale, 0.0};
    const double* parameters[2] = {weights, basis};
    ASSERT_TRUE(cost.Evaluate(parameters, r, nullptr));
    for (double v : r) EXPECT_EQ(v, 0.0);
  }
  // Weight 2 × a and basis 2 ÷ a: the same residual.
  const double weights[2] = {1.0, 0.8};
  const double* parameters[2] = {weights, basis};
  double reference[3];
  ASSERT_TRUE(cost.Evaluate(parameters, reference, nullptr));
  const double a = 4.0;
  const double scaled_weights[2] = {1.0, 0.8 * a};
  const double scaled_basis[6] = {1.0, 2.0, 3.0, 0.5 / a, -1.0 / a, 4.0 / a};
  const double* scaled[2] = {scaled_weights, scaled_basis};
  ASSERT_TRUE(cost.Evaluate(scaled, r, nullptr));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r[i], reference[i], 1e-15);
}

TEST(DeformationError, ProductsGramAndBilinearFormAreThoseOfTheJacobian) {
  // What the structured solver reads instead of a stored Jacobian
  // (problems/jacobian_product.h), against Evaluate()'s Jacobian; the form
  // r = s · B_p (m ⊙ l_t), m = (0, 1, …, 1).
  std::mt19937 rng(22);
  for (int k : {1, 2, 5, 12}) {
    DeformationError cost(k, 0.7);
    testing_util::ExpectProductsEqualTheJacobian(cost, cost, &rng);
    testing_util::ExpectGramEqualsTheJacobian(cost, cost, &rng);
    testing_util::ExpectTheBilinearFormGivesTheResidual(cost, cost, &rng);
    BilinearForm form;
    ASSERT_TRUE(cost.GetBilinearForm(&form));
    ASSERT_EQ(static_cast<int>(form.mask.size()), k);
    EXPECT_EQ(form.mask[0], 0.0);
    for (int c = 1; c < k; ++c) EXPECT_EQ(form.mask[c], 1.0);
  }
}

// Its row of problems/extra_terms.cc: one block per frame and point.
TEST(DeformationTerm, OneBlockPerFrameAndPoint) {
  EXPECT_EQ(testing_util::TermBlockCount(kDeformationTerm,
                                         testing_util::TermTestShoe(1)),
            testing_util::kTermFrames * testing_util::kTermPoints);
}

}  // namespace
}  // namespace nrsfm
