// ComputeUncertainty against an independent computation: Ceres' own
// Covariance (dense SVD of the whole Jacobian) with a gauge held by the
// test, and the points' and rotations' Jacobians by central differences
// through the blocks' manifolds; and the selected inverse against a dense
// inverse.
#include "solvers/uncertainty/uncertainty.h"

#include <ceres/covariance.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>
#include <set>
#include <vector>

#include "problems/extra_terms.h"
#include "problems/problem_builder.h"
#include "problems/rotation_manifold.h"
#include "solvers/uncertainty/selected_inverse.h"
#include "tests/synthetic_sequences.h"

namespace nrsfm {
namespace {

TEST(SelectedInverse, MatchesTheDenseInverseOnTheMatrixPattern) {
  // A block-banded SPD matrix with a dense border, like frames coupled by
  // temporal terms plus a shared block.
  const int n = 60;
  std::mt19937 random(3);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j <= i; ++j) {
      if (i - j <= 5 || i >= n - 3) dense(i, j) = dense(j, i) = normal(random);
    }
  }
  dense += n * Eigen::MatrixXd::Identity(n, n);
  const Eigen::SparseMatrix<double> sparse = dense.sparseView();
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(sparse);
  ASSERT_EQ(ldlt.info(), Eigen::Success);
  const SelectedInverse selected(ldlt);
  const Eigen::MatrixXd inverse = dense.inverse();
  int compared = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (dense(i, j) == 0.0) continue;
      EXPECT_NEAR(selected(i, j), inverse(i, j), 1e-12) << i << ", " << j;
      ++compared;
    }
  }
  EXPECT_GT(compared, 11 * n);
}

// The centred camera-frame points of `model` (X̃ of the header), stacked
// per view and point.
Eigen::VectorXd CentredPoints(const Model& model) {
  Eigen::VectorXd out(3 * model.NumViews() * model.num_points);
  for (int t = 0; t < model.num_frames; ++t) {
    for (int c = 0; c < model.num_cameras; ++c) {
      Eigen::Matrix3Xd x = model.ShapeInCamera(t, c);
      const Eigen::Vector3d centre = x.rowwise().mean();
      x.colwise() -= centre;
      out.segment(3 * model.View(t, c) * model.num_points,
                  3 * model.num_points) =
          Eigen::Map<Eigen::VectorXd>(x.data(), x.size());
    }
  }
  return out;
}

struct Reference {
  std::vector<Eigen::Matrix3d> points;
  std::vector<Eigen::Matrix3d> rotations;
};

// σ² Z Σ Zᵀ with Σ from ceres::Covariance on the problem with the blocks
// `held` constant and Z by central differences.
Reference CeresReference(const ProblemOptions& options,
                         const Measurements& measurements, const Model& truth,
                         const std::set<int>& held_rotations,
                         const std::set<int>& held_weights,
                         const std::set<int>& held_points, double sigma) {
  Model model = truth;
  ProblemBuilder builder(&measurements, &model);
  EXPECT_TRUE(builder.AddReprojectionTerms(options).ok());
  EXPECT_TRUE(AddExtraTerms(options, &builder).ok());
  ceres::Problem* problem = builder.problem();
  for (int v : held_rotations) {
    problem->SetParameterBlockConstant(builder.RotationBlock(v, 0));
  }
  for (int t : held_weights) {
    problem->SetParameterBlockConstant(builder.WeightsBlock(t));
  }
  for (int p : held_points) {
    problem->SetParameterBlockConstant(builder.BasisBlock(p));
  }
  std::vector<const double*> blocks;
  std::vector<double*> free_blocks;
  std::vector<double*> all = builder.NonPointBlocks();
  for (double* b : builder.PointBlocks()) all.push_back(b);
  for (double* b : all) {
    if (problem->IsParameterBlockConstant(b)) continue;
    blocks.push_back(b);
    free_blocks.push_back(b);
  }
  ceres::Covariance::Options covariance_options;
  covariance_options.algorithm_type = ceres::DENSE_SVD;
  ceres::Covariance covariance(covariance_options);
  EXPECT_TRUE(covariance.Compute(blocks, problem));
  int n = 0;
  for (const double* b : blocks) n += problem->ParameterBlockTangentSize(b);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>
      sigma_all(n, n);
  EXPECT_TRUE(
      covariance.GetCovarianceMatrixInTangentSpace(blocks, sigma_all.data()));

  // Z by central differences in each block's tangent space.
  const AngleAxisManifold manifold;
  const int F = model.num_frames, P = model.num_points;
  std::set<const double*> rotation_blocks;
  for (int t = 0; t < F; ++t)
    rotation_blocks.insert(builder.RotationBlock(t, 0));
  Eigen::MatrixXd z(3 * F * P, n), zr(3 * F, n);
  const double h = 1e-6;
  int column = 0;
  for (double* block : free_blocks) {
    const int size = problem->ParameterBlockTangentSize(block);
    const bool is_rotation = rotation_blocks.count(block) > 0;
    for (int i = 0; i < size; ++i, ++column) {
      std::vector<double> saved(block, block + size);
      Eigen::VectorXd plus_minus[2];
      for (int sign = 0; sign < 2; ++sign) {
        double delta[3] = {0, 0, 0};
        if (is_rotation) {
          delta[i] = sign == 0 ? h : -h;
          manifold.Plus(saved.data(), delta, block);
        } else {
          block[i] = saved[i] + (sign == 0 ? h : -h);
        }
        plus_minus[sign] = CentredPoints(model);
        std::copy(saved.begin(), saved.end(), block);
      }
      z.col(column) = (plus_minus[0] - plus_minus[1]) / (2 * h);
      zr.col(column).setZero();
      if (is_rotation) {
        for (int t = 0; t < F; ++t) {
          if (builder.RotationBlock(t, 0) == block) zr(3 * t + i, column) = 1;
        }
      }
    }
  }
  // Rotations with the mean over views removed (the held ones count, at 0).
  Eigen::MatrixXd centre = Eigen::MatrixXd::Zero(3 * F, 3 * F);
  for (int t = 0; t < F; ++t) {
    for (int u = 0; u < F; ++u) {
      centre.block<3, 3>(3 * t, 3 * u) =
          ((t == u) - 1.0 / F) * Eigen::Matrix3d::Identity();
    }
  }
  zr = centre * zr;
  const Eigen::MatrixXd points = sigma * sigma * z * sigma_all * z.transpose();
  const Eigen::MatrixXd rotations =
      sigma * sigma * zr * sigma_all * zr.transpose();
  Reference reference;
  for (int k = 0; k < F * P; ++k) {
    reference.points.push_back(points.block<3, 3>(3 * k, 3 * k));
  }
  for (int t = 0; t < F; ++t) {
    reference.rotations.push_back(rotations.block<3, 3>(3 * t, 3 * t));
  }
  return reference;
}

void ExpectEqualCovariances(const Uncertainty& got, const Reference& want,
                            double tolerance) {
  ASSERT_EQ(got.points.size(), want.points.size());
  double largest = 0;
  for (const auto& c : want.points) largest = std::max(largest, c.norm());
  for (size_t k = 0; k < want.points.size(); ++k) {
    EXPECT_LT((got.points[k] - want.points[k]).norm(), tolerance * largest)
        << "point " << k << "\n"
        << got.points[k] << "\n"
        << want.points[k];
  }
  double largest_rotation = 0;
  for (const auto& c : want.rotations) {
    largest_rotation = std::max(largest_rotation, c.norm());
  }
  for (size_t v = 0; v < want.rotations.size(); ++v) {
    EXPECT_LT((got.rotations[v] - want.rotations[v]).norm(),
              tolerance * largest_rotation)
        << "view " << v;
  }
}

TEST(ComputeUncertainty, DataTermMatchesCeresCovarianceUnderAnotherGauge) {
  // F 10, P 12, K 2, 10 % missing, noise 0.01: the truth as the solution.
  const SyntheticSequence sequence =
      testing_util::RandomBasisSequence(10, 12, 2, 0.01, 0.1, 4);
  const double sigma = 0.01;
  UncertaintyOptions options;
  options.noise_std = sigma;
  Uncertainty got;
  ASSERT_TRUE(ComputeUncertainty(options, ProblemOptions(),
                                 sequence.measurements, sequence.truth, &got)
                  .ok());
  EXPECT_EQ(got.gauge_size, 3 + 2 * 2 + 3 * 2);
  EXPECT_EQ(got.noise_std, sigma);
  // The gauge the test holds differs from the function's (view 0, the
  // weights' pivots, the most seen point): the centred points and the
  // mean-removed rotations do not depend on it.
  const Reference want =
      CeresReference(ProblemOptions(), sequence.measurements, sequence.truth,
                     {4}, {2, 7}, {5}, sigma);
  ExpectEqualCovariances(got, want, 1e-7);  // measured ≤ 1e-9
}

TEST(ComputeUncertainty, EstimatesTheNoiseFromTheFitOfTheTruth) {
  // On the noisy tracks the truth's residual estimates σ: 2·cost / (N − n).
  const SyntheticSequence sequence =
      testing_util::RandomBasisSequence(60, 30, 2, 0.02, 0.0, 5);
  Uncertainty got;
  ASSERT_TRUE(ComputeUncertainty(UncertaintyOptions(), ProblemOptions(),
                                 sequence.measurements, sequence.truth, &got)
                  .ok());
  EXPECT_TRUE(got.noise_estimated);
  EXPECT_EQ(got.num_residuals, 2 * 60 * 30);
  EXPECT_EQ(got.num_parameters, 60 * 7 + 30 * 6 - got.gauge_size);
  // The truth fits the noise exactly, not a least-squares solution: σ̂ is
  // √(N / (N − n)) × the sample std, 0.02 · 1.09 ± 3 % (N = 3600).
  EXPECT_NEAR(got.noise_std,
              0.02 * std::sqrt(3600.0 / (3600 - got.num_parameters)), 0.0007);
}

TEST(ComputeUncertainty, WithATemporalTermMatchesCeresUnderTheSameGauge) {
  const SyntheticSequence sequence =
      testing_util::RandomBasisSequence(10, 12, 2, 0.01, 0.1, 6);
  ProblemOptions problem;
  problem.term_weights[kTemporalShapeTerm] = 0.5;
  UncertaintyOptions options;
  options.noise_std = 0.01;
  Uncertainty got;
  ASSERT_TRUE(ComputeUncertainty(options, problem, sequence.measurements,
                                 sequence.truth, &got)
                  .ok());
  // The function's gauge: view 0, the pivots of the weights' QR, the point
  // seen most (the first of the most seen).
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(sequence.truth.weights);
  const Eigen::VectorXi seen = sequence.measurements.VisiblePerPoint();
  int most = 0;
  seen.maxCoeff(&most);
  const Reference want = CeresReference(
      problem, sequence.measurements, sequence.truth, {0},
      {qr.colsPermutation().indices()(0), qr.colsPermutation().indices()(1)},
      {most}, 0.01);
  ExpectEqualCovariances(got, want, 1e-7);  // measured ≤ 1e-9
}

TEST(ComputeUncertainty, AnUndeterminedBasisIsAnError) {
  // Basis shape 2 has weight 0 in every frame: the data do not see it.
  SyntheticSequence sequence =
      testing_util::RandomBasisSequence(10, 12, 2, 0.01, 0.0, 7);
  sequence.truth.weights.row(1).setZero();
  sequence.truth.weights(1, 0) = 1e-300;  // keeps the QR's pivots defined
  UncertaintyOptions options;
  options.noise_std = 0.01;
  Uncertainty got;
  const Status status = ComputeUncertainty(
      options, ProblemOptions(), sequence.measurements, sequence.truth, &got);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("singular"), std::string::npos)
      << status.message();
}

TEST(UncertaintyOptions, CheckNamesTheBadField) {
  UncertaintyOptions options;
  options.noise_std = -1;
  EXPECT_NE(options.Check().message().find("noise_std"), std::string::npos);
  options = UncertaintyOptions();
  options.max_dense_parameters = 0;
  EXPECT_NE(options.Check().message().find("max_dense_parameters"),
            std::string::npos);
}

}  // namespace
}  // namespace nrsfm
