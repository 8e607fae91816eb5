#include <ceres/gradient_checker.h>
#include <ceres/numeric_diff_options.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "problems/problem_builder.h"
#include "problems/reprojection_cost_function.h"
#include "tests/problems/reprojection_error_oracle.h"

namespace nrsfm {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Parameter values of one residual block: rotation, translation, weights,
// basis, scale (contiguous, in the block order).
struct Blocks {
  explicit Blocks(int k) : num_bases(k), values(3 + 2 + k + 3 * k + 1) {}
  double* rotation() { return values.data(); }
  double* translation() { return values.data() + 3; }
  double* weights() { return values.data() + 5; }
  double* basis() { return values.data() + 5 + num_bases; }
  double* scale() { return values.data() + 5 + 4 * num_bases; }
  std::vector<const double*> Pointers(bool with_scale) {
    std::vector<const double*> p = {rotation(), translation(), weights(),
                                    basis()};
    if (with_scale) p.push_back(scale());
    return p;
  }
  int num_bases;
  std::vector<double> values;
};

Blocks RandomBlocks(int k, std::mt19937* rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Blocks b(k);
  for (double& v : b.values) v = uniform(*rng);
  b.scale()[0] = 0.7 + 0.5 * std::abs(uniform(*rng));
  return b;
}

Eigen::Vector2d Evaluate(const ceres::CostFunction& cost,
                         std::vector<const double*> parameters) {
  Eigen::Vector2d r;
  EXPECT_TRUE(cost.Evaluate(parameters.data(), r.data(), nullptr));
  return r;
}

// Every cost function for K bases that the library can build, and the
// oracle.
std::vector<std::unique_ptr<ceres::CostFunction>> AllForms(
    int k, bool with_scale, const Eigen::Vector2d& observation,
    double sqrt_weight) {
  std::vector<std::unique_ptr<ceres::CostFunction>> forms;
  forms.emplace_back(
      CreateReprojectionCostFunction(k, with_scale, observation, sqrt_weight));
  forms.emplace_back(DynamicReprojectionError::Create(
      k, with_scale, observation, sqrt_weight));
  forms.emplace_back(new ReprojectionCostFunction<Eigen::Dynamic>(
      k, with_scale, observation, sqrt_weight));
  return forms;
}

// Hand computation, K = 2: ω = (0, 0, π/2) turns x into y and y into −x.
//   X = 2·(1, 0, 3) + (−1)·(0, 1, 1) = (2, −1, 5)
//   R X = (1, 2, 5), Π R X = (1, 2)
//   monocular:  r = 3 · ((1, 2) + (10, −4) − (12, −1)) = 3 · (−1, −1)
//   scale 0.5:  r = 3 · ((0.5, 1) + (10, −4) − (12, −1)) = 3 · (−1.5, −2)
TEST(ReprojectionError, HandComputedResidualsForEveryForm) {
  Blocks b(2);
  const double rotation[3] = {0.0, 0.0, kPi / 2};
  const double translation[2] = {10.0, -4.0};
  const double weights[2] = {2.0, -1.0};
  const double basis[6] = {1.0, 0.0, 3.0, 0.0, 1.0, 1.0};
  std::copy(rotation, rotation + 3, b.rotation());
  std::copy(translation, translation + 2, b.translation());
  std::copy(weights, weights + 2, b.weights());
  std::copy(basis, basis + 6, b.basis());
  b.scale()[0] = 0.5;
  const Eigen::Vector2d observation(12.0, -1.0);
  const double sqrt_weight = 3.0;  // w_obs = 9

  std::vector<std::unique_ptr<ceres::CostFunction>> plain =
      AllForms(2, false, observation, sqrt_weight);
  plain.emplace_back(ReprojectionError<2>::Create(observation, sqrt_weight));
  for (const auto& cost : plain) {
    const Eigen::Vector2d r = Evaluate(*cost, b.Pointers(false));
    EXPECT_NEAR(r.x(), -3.0, 1e-12);
    EXPECT_NEAR(r.y(), -3.0, 1e-12);
  }
  std::vector<std::unique_ptr<ceres::CostFunction>> scaled =
      AllForms(2, true, observation, sqrt_weight);
  scaled.emplace_back(
      ReprojectionError<2>::CreateScaled(observation, sqrt_weight));
  for (const auto& cost : scaled) {
    const Eigen::Vector2d r = Evaluate(*cost, b.Pointers(true));
    EXPECT_NEAR(r.x(), -4.5, 1e-12);
    EXPECT_NEAR(r.y(), -6.0, 1e-12);
  }
}

// Hand-computed Jacobians at ω = 0 (R = I, ∂(R X)/∂ω = −[X]×), K = 1,
// X = l·b = 2·(1, 2, 3) = (2, 4, 6), s = 1, sqrt(w) = 1:
//   ∂r/∂ω = Π(−[X]×) = [[0, 6, −4], [−6, 0, 2]]
//   ∂r/∂l = Π b = (1, 2),  ∂r/∂b = l·Π = [[2, 0, 0], [0, 2, 0]].
TEST(ReprojectionError, HandComputedJacobianAtZeroRotation) {
  Blocks b(1);
  std::fill(b.values.begin(), b.values.end(), 0.0);
  b.weights()[0] = 2.0;
  b.basis()[0] = 1.0;
  b.basis()[1] = 2.0;
  b.basis()[2] = 3.0;
  for (const auto& cost : AllForms(1, false, Eigen::Vector2d::Zero(), 1.0)) {
    double d_rotation[6], d_translation[4], d_weights[2], d_basis[6];
    double* jacobians[4] = {d_rotation, d_translation, d_weights, d_basis};
    double r[2];
    ASSERT_TRUE(cost->Evaluate(b.Pointers(false).data(), r, jacobians));
    const double expected_rotation[6] = {0, 6, -4, -6, 0, 2};
    for (int i = 0; i < 6; ++i)
      EXPECT_NEAR(d_rotation[i], expected_rotation[i], 1e-12);
    const double expected_translation[4] = {1, 0, 0, 1};
    for (int i = 0; i < 4; ++i)
      EXPECT_EQ(d_translation[i], expected_translation[i]);
    EXPECT_NEAR(d_weights[0], 1.0, 1e-12);
    EXPECT_NEAR(d_weights[1], 2.0, 1e-12);
    const double expected_basis[6] = {2, 0, 0, 0, 2, 0};
    for (int i = 0; i < 6; ++i)
      EXPECT_NEAR(d_basis[i], expected_basis[i], 1e-12);
  }
}

void ExpectGradientCheckPasses(const ceres::CostFunction& cost, Blocks* b,
                               bool with_scale) {
  ceres::NumericDiffOptions numeric_options;
  const std::vector<const ceres::Manifold*>* euclidean = nullptr;
  ceres::GradientChecker checker(&cost, euclidean, numeric_options);
  ceres::GradientChecker::ProbeResults results;
  EXPECT_TRUE(checker.Probe(b->Pointers(with_scale).data(), 1e-7, &results))
      << results.error_log;
}

TEST(ReprojectionError, GradientCheckerForSeveralK) {
  std::mt19937 rng(7);
  for (const int k : {1, 2, 3, 7, 12, 16, 17, 20}) {
    for (const bool with_scale : {false, true}) {
      SCOPED_TRACE("K = " + std::to_string(k) +
                   (with_scale ? " with scale" : " monocular"));
      Blocks b = RandomBlocks(k, &rng);
      const Eigen::Vector2d observation(0.3, -0.2);
      for (const auto& cost : AllForms(k, with_scale, observation, 1.7)) {
        ExpectGradientCheckPasses(*cost, &b, with_scale);
      }
    }
  }
  // The compile-time autodiff functor for a few K.
  Blocks b3 = RandomBlocks(3, &rng);
  std::unique_ptr<ceres::CostFunction> ad3(
      ReprojectionError<3>::Create(Eigen::Vector2d(0.1, 0.4), 0.5));
  ExpectGradientCheckPasses(*ad3, &b3, false);
  Blocks b12 = RandomBlocks(12, &rng);
  std::unique_ptr<ceres::CostFunction> ad12(
      ReprojectionError<12>::CreateScaled(Eigen::Vector2d(0.1, 0.4), 2.0));
  ExpectGradientCheckPasses(*ad12, &b12, true);
}

// The hand-written Jacobian equals autodiff to rounding, including at and
// near ω = 0 where the angle-axis formulas switch to their Taylor form.
TEST(ReprojectionError, HandWrittenJacobianEqualsAutodiff) {
  std::mt19937 rng(11);
  for (const int k : {1, 4, 12, 16, 17}) {
    for (const double rotation_norm : {0.0, 1e-9, 1e-4, -1.0}) {
      for (const bool with_scale : {false, true}) {
        Blocks b = RandomBlocks(k, &rng);
        if (rotation_norm >= 0.0) {
          const Eigen::Vector3d axis = Eigen::Vector3d(1, -2, 0.5).normalized();
          Eigen::Map<Eigen::Vector3d>(b.rotation()) = rotation_norm * axis;
        }
        const Eigen::Vector2d observation(0.2, 0.1);
        std::unique_ptr<ceres::CostFunction> by_hand(
            CreateReprojectionCostFunction(k, with_scale, observation, 1.3));
        std::unique_ptr<ceres::CostFunction> autodiff(
            DynamicReprojectionError::Create(k, with_scale, observation, 1.3));
        const std::vector<int>& sizes = by_hand->parameter_block_sizes();
        ASSERT_EQ(sizes, autodiff->parameter_block_sizes());
        std::vector<std::vector<double>> j1, j2;
        std::vector<double*> p1, p2;
        for (int size : sizes) {
          j1.emplace_back(2 * size, 0.0);
          j2.emplace_back(2 * size, 0.0);
        }
        for (size_t i = 0; i < sizes.size(); ++i) {
          p1.push_back(j1[i].data());
          p2.push_back(j2[i].data());
        }
        double r1[2], r2[2];
        ASSERT_TRUE(
            by_hand->Evaluate(b.Pointers(with_scale).data(), r1, p1.data()));
        ASSERT_TRUE(
            autodiff->Evaluate(b.Pointers(with_scale).data(), r2, p2.data()));
        EXPECT_NEAR(r1[0], r2[0], 1e-13);
        EXPECT_NEAR(r1[1], r2[1], 1e-13);
        for (size_t i = 0; i < sizes.size(); ++i) {
          for (size_t j = 0; j < j1[i].size(); ++j) {
            EXPECT_NEAR(j1[i][j], j2[i][j], 1e-12)
                << "K = " << k << ", |ω| = " << rotation_norm << ", block "
                << i;
          }
        }
      }
    }
  }
}

// The basis block's Jacobian is l_k · A with the factor A the cost function
// reports (what the structured solver keeps instead of the 2 × 3K block),
// and EvaluateWithBasisFactor gives Evaluate's residuals and other blocks.
TEST(ReprojectionError, BasisJacobianIsWeightTimesTheReportedFactor) {
  std::mt19937 rng(5);
  for (const int k : {1, 3, 12, 17}) {
    for (const bool with_scale : {false, true}) {
      Blocks b = RandomBlocks(k, &rng);
      std::unique_ptr<ceres::CostFunction> cost(CreateReprojectionCostFunction(
          k, with_scale, Eigen::Vector2d(0.3, -0.2), 1.7));
      const auto* factor_source =
          dynamic_cast<const BasisJacobianFactor*>(cost.get());
      ASSERT_NE(factor_source, nullptr);
      EXPECT_EQ(factor_source->num_bases(), k);
      const std::vector<int>& sizes = cost->parameter_block_sizes();
      std::vector<std::vector<double>> full(sizes.size()),
          partial(sizes.size());
      std::vector<double*> full_ptr, partial_ptr;
      for (size_t i = 0; i < sizes.size(); ++i) {
        full[i].assign(2 * sizes[i], 0.0);
        partial[i].assign(2 * sizes[i], -7.0);
        full_ptr.push_back(full[i].data());
        partial_ptr.push_back(
            i == BasisJacobianFactor::kBasisSlot ? nullptr : partial[i].data());
      }
      double r_full[2], r_partial[2], a[6];
      const std::vector<const double*> parameters = b.Pointers(with_scale);
      ASSERT_TRUE(cost->Evaluate(parameters.data(), r_full, full_ptr.data()));
      ASSERT_TRUE(factor_source->EvaluateWithBasisFactor(
          parameters.data(), r_partial, partial_ptr.data(), a, nullptr));
      EXPECT_EQ(r_full[0], r_partial[0]);
      EXPECT_EQ(r_full[1], r_partial[1]);
      for (size_t i = 0; i < sizes.size(); ++i) {
        if (i == BasisJacobianFactor::kBasisSlot) continue;
        EXPECT_EQ(full[i], partial[i]) << "block " << i;
      }
      // The rotation's derivatives formed by the caller: the same bits.
      const ProjectedRotation rotation = ProjectedRotation::FromAngleAxis(
          parameters[BasisJacobianFactor::kRotationSlot]);
      for (std::vector<double>& block : partial) block.assign(block.size(), 9);
      double r_given[2], a_given[6];
      ASSERT_TRUE(factor_source->EvaluateWithBasisFactor(
          parameters.data(), r_given, partial_ptr.data(), a_given, &rotation));
      EXPECT_EQ(r_full[0], r_given[0]);
      EXPECT_EQ(r_full[1], r_given[1]);
      EXPECT_TRUE(std::equal(a, a + 6, a_given));
      for (size_t i = 0; i < sizes.size(); ++i) {
        if (i == BasisJacobianFactor::kBasisSlot) continue;
        EXPECT_EQ(full[i], partial[i]) << "block " << i << " (rotation given)";
      }
      const double* weights = parameters[BasisJacobianFactor::kWeightsSlot];
      const std::vector<double>& jb = full[BasisJacobianFactor::kBasisSlot];
      for (int row = 0; row < 2; ++row) {
        for (int kk = 0; kk < k; ++kk) {
          for (int col = 0; col < 3; ++col) {
            EXPECT_NEAR(jb[row * 3 * k + 3 * kk + col],
                        weights[kk] * a[3 * row + col], 1e-14)
                << "K = " << k << ", row " << row << ", basis " << kk
                << ", col " << col;
          }
        }
      }
    }
  }
}

TEST(ReprojectionError, FactoryDispatchesOnK) {
  for (const int k : {1, 16, 17, 40}) {
    std::unique_ptr<ceres::CostFunction> cost(
        CreateReprojectionCostFunction(k, false, Eigen::Vector2d::Zero(), 1.0));
    EXPECT_EQ(cost->num_residuals(), 2);
    EXPECT_EQ(cost->parameter_block_sizes(),
              (std::vector<int>{3, 2, k, 3 * k}));
    const bool is_static = k <= kMaxStaticBases;
    EXPECT_EQ(dynamic_cast<ReprojectionCostFunction<Eigen::Dynamic>*>(
                  cost.get()) == nullptr,
              is_static);
  }
  std::unique_ptr<ceres::CostFunction> scaled(
      CreateReprojectionCostFunction(5, true, Eigen::Vector2d::Zero(), 1.0));
  EXPECT_EQ(scaled->parameter_block_sizes(),
            (std::vector<int>{3, 2, 5, 15, 1}));
  EXPECT_NE(dynamic_cast<ReprojectionCostFunction<5>*>(scaled.get()), nullptr);
}

}  // namespace
}  // namespace nrsfm
