// Checks of a cost function's JacobianProduct (problems/jacobian_product.h)
// against the Jacobian its own Evaluate() returns, at random parameters:
// the products J x and Jᵀ y, the Gram blocks J_aᵀ J_b and their diagonals,
// and the bilinear form r = s · D λ.
#ifndef NRSFM_TESTS_PROBLEMS_JACOBIAN_PRODUCT_TEST_UTIL_H_
#define NRSFM_TESTS_PROBLEMS_JACOBIAN_PRODUCT_TEST_UTIL_H_

#include <ceres/cost_function.h>
#include <gtest/gtest.h>

#include <cstddef>
#include <random>
#include <vector>

#include "problems/jacobian_product.h"
#include "tests/problems/functor_test_util.h"

namespace nrsfm {
namespace testing_util {

// `cost` evaluated with its Jacobian at random parameters: the values and
// sizes of its blocks, its residuals and the row-major m × size Jacobian
// of each block.
struct EvaluatedTerm {
  EvaluatedTerm(const ceres::CostFunction& cost, std::mt19937* rng)
      : m(cost.num_residuals()), residuals(m) {
    for (const int size : cost.parameter_block_sizes()) {
      sizes.push_back(size);
      values.push_back(Random(size, rng));
      jacobian.emplace_back(static_cast<std::size_t>(m) * size);
    }
    std::vector<double*> jacobians;
    for (std::size_t b = 0; b < values.size(); ++b) {
      parameters.push_back(values[b].data());
      jacobians.push_back(jacobian[b].data());
    }
    EXPECT_TRUE(
        cost.Evaluate(parameters.data(), residuals.data(), jacobians.data()));
  }
  double J(int block, int row, int column) const {
    return jacobian[block][row * sizes[block] + column];
  }
  int m;
  std::vector<int> sizes;
  std::vector<std::vector<double>> values;
  std::vector<const double*> parameters;
  std::vector<double> residuals;
  std::vector<std::vector<double>> jacobian;
};

// J x for every subset of blocks (a null x[b] is zero) and Jᵀ y for every
// subset of outputs, both added to what the outputs hold.
inline void ExpectProductsEqualTheJacobian(const ceres::CostFunction& cost,
                                           const JacobianProduct& product,
                                           std::mt19937* rng) {
  const EvaluatedTerm e(cost, rng);
  const int n = static_cast<int>(e.sizes.size());
  const std::vector<double> y = Random(e.m, rng);
  std::vector<std::vector<double>> x;
  for (int b = 0; b < n; ++b) x.push_back(Random(e.sizes[b], rng));
  for (int subset = 0; subset < (1 << n); ++subset) {
    std::vector<const double*> xs(n, nullptr);
    std::vector<double*> outs(n, nullptr);
    std::vector<double> got_y(e.m, 0.5), want_y(e.m, 0.5);
    std::vector<std::vector<double>> got_x(n), want_x(n);
    for (int b = 0; b < n; ++b) {
      const bool on = (subset >> b) & 1;
      got_x[b].assign(e.sizes[b], 0.1 * b);
      want_x[b] = got_x[b];
      if (!on) continue;
      xs[b] = x[b].data();
      outs[b] = got_x[b].data();
      for (int i = 0; i < e.m; ++i) {
        for (int j = 0; j < e.sizes[b]; ++j) {
          want_y[i] += e.J(b, i, j) * x[b][j];
          want_x[b][j] += e.J(b, i, j) * y[i];
        }
      }
    }
    product.AddJacobianProduct(e.parameters.data(), xs.data(), got_y.data());
    product.AddJacobianTransposeProduct(e.parameters.data(), y.data(),
                                        outs.data());
    for (int i = 0; i < e.m; ++i) {
      EXPECT_NEAR(got_y[i], want_y[i], 1e-13) << "subset " << subset;
    }
    for (int b = 0; b < n; ++b) {
      for (int j = 0; j < e.sizes[b]; ++j) {
        EXPECT_NEAR(got_x[b][j], want_x[b][j], 1e-13)
            << "subset " << subset << ", block " << b << ", " << j;
      }
    }
  }
}

// J_aᵀ J_b for every pair of blocks, added to a column-major buffer with a
// leading dimension larger than the block, and diag(J_aᵀ J_a).
inline void ExpectGramEqualsTheJacobian(const ceres::CostFunction& cost,
                                        const JacobianProduct& product,
                                        std::mt19937* rng) {
  ASSERT_TRUE(product.ProvidesGram());
  const EvaluatedTerm e(cost, rng);
  const int n = static_cast<int>(e.sizes.size());
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) {
      const int ld = e.sizes[a] + 2;
      std::vector<double> got(static_cast<std::size_t>(ld) * e.sizes[b], 0.25);
      product.AddGram(e.parameters.data(), a, b, got.data(), ld);
      for (int j = 0; j < e.sizes[b]; ++j) {
        for (int i = 0; i < ld; ++i) {
          double want = 0.25;
          for (int row = 0; row < e.m && i < e.sizes[a]; ++row) {
            want += e.J(a, row, i) * e.J(b, row, j);
          }
          EXPECT_NEAR(got[i + static_cast<std::size_t>(j) * ld], want, 1e-13)
              << "blocks " << a << ", " << b << ", entry " << i << ", " << j;
        }
      }
    }
    std::vector<double> diagonal(e.sizes[a], -0.5);
    product.AddGramDiagonal(e.parameters.data(), a, diagonal.data());
    for (int i = 0; i < e.sizes[a]; ++i) {
      double want = -0.5;
      for (int row = 0; row < e.m; ++row)
        want += e.J(a, row, i) * e.J(a, row, i);
      EXPECT_NEAR(diagonal[i], want, 1e-13) << "block " << a << ", " << i;
    }
  }
}

// The residual is s · D λ as GetBilinearForm describes it: λ = m ⊙ Σ_j σ_j
// l_j over the weights blocks, D = Σ_i τ_i B_i over the basis blocks
// (3K values read as 3 × K, column k = values 3k … 3k + 2).
inline void ExpectTheBilinearFormGivesTheResidual(
    const ceres::CostFunction& cost, const JacobianProduct& product,
    std::mt19937* rng) {
  BilinearForm form;
  ASSERT_TRUE(product.GetBilinearForm(&form));
  const EvaluatedTerm e(cost, rng);
  const int k = form.num_bases;
  ASSERT_EQ(e.m, 3);
  ASSERT_EQ(form.signs.size(), e.sizes.size());
  ASSERT_EQ(form.is_weights.size(), e.sizes.size());
  std::vector<double> lambda(k, 0.0), d(3 * k, 0.0);
  for (std::size_t b = 0; b < e.sizes.size(); ++b) {
    ASSERT_EQ(e.sizes[b], form.is_weights[b] ? k : 3 * k) << b;
    std::vector<double>& sum = form.is_weights[b] ? lambda : d;
    for (int i = 0; i < e.sizes[b]; ++i) {
      sum[i] += form.signs[b] * e.values[b][i];
    }
  }
  for (int c = 0; c < k; ++c) {
    if (!form.mask.empty()) lambda[c] *= form.mask[c];
  }
  for (int row = 0; row < 3; ++row) {
    double want = 0.0;
    for (int c = 0; c < k; ++c) want += d[3 * c + row] * lambda[c];
    EXPECT_NEAR(e.residuals[row], form.scale * want, 1e-13) << row;
  }
}

}  // namespace testing_util
}  // namespace nrsfm

#endif  // NRSFM_TESTS_PROBLEMS_JACOBIAN_PRODUCT_TEST_UTIL_H_
