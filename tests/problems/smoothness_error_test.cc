// Hand-computed residuals and Jacobian checks of problems/smoothness_error.h.
#include "problems/smoothness_error.h"

#include <ceres/gradient_checker.h>
#include <ceres/numeric_diff_options.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <memory>
#include <numeric>
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
  // Stencil i, j, m with weights 0.25 and 0.75: c = (1, −0.25, −0.75).
  const int k = 2;
  const double l[2] = {2.0, -1.0};
  const double b_i[6] = {1, 2, 3, 4, 5, 6};
  const double b_j[6] = {0.5, 2, 4, 4, 3, 7};
  const double b_m[6] = {1, 6, 2, 0, 1, 1};
  SmoothnessError cost(k, 3.0, {1.0, -0.25, -0.75});
  EXPECT_EQ(cost.num_residuals(), 3);
  ASSERT_EQ(cost.parameter_block_sizes(), (std::vector<int32_t>{2, 6, 6, 6}));
  const double* parameters[4] = {l, b_i, b_j, b_m};
  double r[3], j_l[6], j_i[18], j_j[18], j_m[18];
  double* jacobians[4] = {j_l, j_i, j_j, j_m};
  ASSERT_TRUE(cost.Evaluate(parameters, r, jacobians));
  // Σ c b: shape 1 (1 − 0.125 − 0.75, 2 − 0.5 − 4.5, 3 − 1 − 1.5) =
  // (0.125, −3, 0.5); shape 2 (4 − 1 − 0, 5 − 0.75 − 0.75, 6 − 1.75 − 0.75)
  // = (3, 3.5, 3.5). The frame: 2 · shape 1 − shape 2 = (−2.75, −9.5,
  // −2.5), times s = 3.
  const double expected[3] = {-8.25, -28.5, -7.5};
  for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(r[i], expected[i]) << i;
  // ∂r/∂l_k = s Σ c b_k: row c, column k.
  const double expected_l[6] = {0.375, 9.0, -9.0, 10.5, 1.5, 10.5};
  for (int i = 0; i < 6; ++i) EXPECT_DOUBLE_EQ(j_l[i], expected_l[i]) << i;
  // ∂r/∂b_m = s c_m [l_1 I, l_2 I].
  const double* blocks[3] = {j_i, j_j, j_m};
  const double c_m[3] = {1.0, -0.25, -0.75};
  for (int m = 0; m < 3; ++m) {
    for (int c = 0; c < 3; ++c) {
      for (int col = 0; col < 6; ++col) {
        const double want = col % 3 == c ? 3.0 * c_m[m] * l[col / 3] : 0.0;
        EXPECT_DOUBLE_EQ(blocks[m][6 * c + col], want) << m;
      }
    }
  }
}

TEST(SmoothnessError, GradientChecker) {
  std::mt19937 rng(3);
  for (const int k : {1, 3, 7}) {
    for (const std::vector<double>& c :
         {std::vector<double>{1.0, -1.0},
          std::vector<double>{1.0, -0.2, -0.5, -0.3}}) {
      SmoothnessError cost(k, 0.7, c);
      std::vector<std::vector<double>> values = {Random(k, &rng)};
      std::vector<const double*> parameters = {values[0].data()};
      for (std::size_t m = 0; m < c.size(); ++m) {
        values.push_back(Random(3 * k, &rng));
      }
      for (std::size_t m = 1; m < values.size(); ++m) {
        parameters.push_back(values[m].data());
      }
      ExpectGradientCheckPasses(cost, parameters);
    }
  }
}

TEST(SmoothnessError, ProductsAndBilinearFormAreThoseOfTheJacobian) {
  // J x and Jᵀ y formed from the parameters (problems/jacobian_product.h)
  // against the Jacobian Evaluate() returns; the form
  // r = s · (Σ_m c_m B_m) l_t.
  std::mt19937 rng(5);
  for (int k : {1, 3, 7}) {
    SmoothnessError cost(k, 0.8, {1.0, -0.6, -0.1, -0.3});
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
  const SmoothnessError cost(k, 1.0, {1.0, -1.0});
  const double* before[3] = {l, b_i, b_j};
  const double* after[3] = {l2, bi2, bj2};
  double r[3], r2[3];
  ASSERT_TRUE(cost.Evaluate(before, r, nullptr));
  ASSERT_TRUE(cost.Evaluate(after, r2, nullptr));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r2[i], r[i], 1e-12) << i;
}

// Orthographic views (1 camera) of the P × 3 points `shape` (rows X, Y, Z)
// turned by `num_frames` rotations about an axis near the optical axis;
// `hidden` is not seen in frame 0.
Measurements ViewsOf(const Eigen::Matrix3Xd& shape, int num_frames,
                     int hidden) {
  Measurements m;
  m.num_frames = num_frames;
  m.num_points = static_cast<int>(shape.cols());
  m.W.resize(2 * num_frames, shape.cols());
  m.visible = VisibilityMask::Constant(num_frames, shape.cols(), true);
  for (int t = 0; t < num_frames; ++t) {
    const Eigen::Matrix3d r =
        Eigen::AngleAxisd(0.3 * t + 0.1,
                          Eigen::Vector3d(0.2, 0.3, 1.0).normalized())
            .toRotationMatrix();
    m.W.middleRows(2 * t, 2) = (r * shape).topRows(2);
  }
  m.visible(0, hidden) = false;
  m.W.col(hidden).segment(0, 2).setConstant(0.0);
  return m;
}

// Σ over the stencils of |S_i − Σ_j w_ij S_j| (K = 1, l = 1, s = 1).
double StencilResidualSum(const std::vector<SmoothnessStencil>& stencils,
                          const Eigen::Matrix3Xd& shape) {
  double sum = 0.0;
  for (const SmoothnessStencil& stencil : stencils) {
    EXPECT_NEAR(
        std::accumulate(stencil.weights.begin(), stencil.weights.end(), 0.0),
        1.0, 1e-12);
    std::vector<double> c = {1.0};
    const double one = 1.0;
    std::vector<const double*> parameters = {&one,
                                             shape.col(stencil.point).data()};
    for (std::size_t q = 0; q < stencil.neighbours.size(); ++q) {
      c.push_back(-stencil.weights[q]);
      parameters.push_back(shape.col(stencil.neighbours[q]).data());
    }
    const SmoothnessError cost(1, 1.0, c);
    double r[3];
    EXPECT_TRUE(cost.Evaluate(parameters.data(), r, nullptr));
    sum += Eigen::Vector3d(r[0], r[1], r[2]).norm();
  }
  return sum;
}

TEST(SmoothnessStencils, ZeroOnAPlaneAtAnySlantNotOnACurvedSurface) {
  // 40 points of a slanted plane seen in 3 orthographic views (point 5 not
  // in frame 0, so frame 1 is the reference): every frame's shape is an
  // affine function of
  // the image, so every stencil reproduces every point (to ε); the same
  // points on a sphere of radius 2 do not.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int p = 40;
  Eigen::Matrix3Xd plane(3, p), sphere(3, p);
  for (int i = 0; i < p; ++i) {
    const double x = u(rng), y = u(rng);
    plane.col(i) << x, y, 0.6 * x - 0.4 * y + 3.0;
    sphere.col(i) << x, y, std::sqrt(4.0 - x * x - y * y);
  }
  for (const Eigen::Matrix3Xd* shape : {&plane, &sphere}) {
    const Measurements m = ViewsOf(*shape, 3, 5);
    std::vector<SmoothnessStencil> stencils;
    int reference = -1;
    ASSERT_TRUE(ComputeSmoothnessStencils(m, DelaunayEdgesOptions(), &stencils,
                                          &reference)
                    .ok());
    EXPECT_EQ(reference, 1);  // the first view that sees all 40
    ASSERT_EQ(static_cast<int>(stencils.size()), p);
    for (int i = 0; i < p; ++i) EXPECT_EQ(stencils[i].point, i);
    const double sum = StencilResidualSum(stencils, *shape);
    if (shape == &plane) {
      EXPECT_LT(sum / p, 1e-5);
    } else {
      EXPECT_GT(sum / p, 1e-3);
    }
  }
}

TEST(SmoothnessStencils, WeightsReproduceThePositionOrComeNearest) {
  // Three points of a line and one above them (two triangles).
  Measurements m;
  m.num_frames = 1;
  m.num_points = 4;
  m.W.resize(2, 4);
  m.W << 0.0, 1.0, 3.0, 1.0, 0.0, 0.0, 0.0, 5.0;
  m.visible = VisibilityMask::Constant(1, 4, true);
  std::vector<SmoothnessStencil> stencils;
  ASSERT_TRUE(
      ComputeSmoothnessStencils(m, DelaunayEdgesOptions(), &stencils).ok());
  ASSERT_EQ(stencils.size(), 4u);
  // Triangles (0, 1, 3) and (1, 2, 3): point 0's neighbours 1 and 3.
  const SmoothnessStencil& zero = stencils[0];
  ASSERT_EQ(zero.neighbours, (std::vector<int>{1, 3}));
  // x_0 = (0, 0) from (1, 0) and (1, 5): no affine combination of two
  // points off the line through x_0 reproduces it; the weights sum to 1 and
  // are the nearest, (1, 0)'s weight far the larger.
  EXPECT_NEAR(zero.weights[0] + zero.weights[1], 1.0, 1e-12);
  EXPECT_GT(zero.weights[0], 0.9);
  const SmoothnessStencil& one = stencils[1];
  ASSERT_EQ(one.neighbours, (std::vector<int>{0, 2, 3}));
  // x_1 = (1, 0) = 2/3 x_0 + 1/3 x_2 + 0 x_3.
  EXPECT_NEAR(one.weights[0], 2.0 / 3.0, 1e-5);
  EXPECT_NEAR(one.weights[1], 1.0 / 3.0, 1e-5);
  EXPECT_NEAR(one.weights[2], 0.0, 1e-5);
}

// Its row of problems/extra_terms.cc: one block per frame and stencil.
TEST(SmoothnessTerm, OneBlockPerFrameAndStencil) {
  const SyntheticSequence s = testing_util::TermTestShoe(1);
  std::vector<SmoothnessStencil> stencils;
  ASSERT_TRUE(ComputeSmoothnessStencils(s.measurements, DelaunayEdgesOptions(),
                                        &stencils)
                  .ok());
  EXPECT_EQ(static_cast<int>(stencils.size()), testing_util::kTermPoints);
  EXPECT_EQ(testing_util::TermBlockCount(kSmoothnessTerm, s),
            s.truth.num_frames * static_cast<int>(stencils.size()));
}

}  // namespace
}  // namespace nrsfm
