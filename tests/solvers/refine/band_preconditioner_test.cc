// BandPreconditioner (solvers/refine/band_preconditioner.h) against the
// dense block it stands for, formed from Ceres' own Jacobian of the same
// problem (tests/solvers/refine/dense_oracle.h): M = J_fᵀJ_f + μD_f over the
// reduced columns (frame groups, then the shared blocks), without the
// coupling the elimination of the points adds. Every residual block holds
// groups at most StructuredBlocks::band apart, so the band holds all of
// J_fᵀJ_f and M⁻¹ is that block's inverse.
#include "solvers/refine/band_preconditioner.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <algorithm>
#include <random>

#include "solvers/refine/schur_elimination.h"
#include "solvers/refine/structured_jacobian.h"
#include "tests/solvers/refine/dense_oracle.h"

namespace nrsfm {
namespace {

// Measured (this test, both cases, μ 1e-4 and 1, 1 and 2 threads alike):
// M⁻¹v within 1.1e-15 of the dense LDLT solve, M (M⁻¹v) within 1.6e-15 of v.
constexpr double kBound = 1e-14;

class BandPreconditionerOracle : public testing::TestWithParam<OracleCase> {};

TEST_P(BandPreconditionerOracle, InvertsTheReducedBlock) {
  const std::unique_ptr<OracleProblem> p = MakeOracleProblem(GetParam());
  const structured::StructuredBlocks& blocks = p->blocks;
  const int nf = blocks.num_reduced;
  ASSERT_GT(blocks.band, 0);
  if (GetParam() == OracleCase::kTwoCamerasRig) {
    ASSERT_GT(blocks.num_shared(), 0);  // the rig blocks: border and corner
  } else {
    ASSERT_EQ(blocks.grids.size(), 3u);
  }
  const DenseJacobian dense = EvaluateDense(blocks, p->builder->problem());
  const Eigen::MatrixXd jf = dense.jacobian.leftCols(nf);
  const Eigen::MatrixXd gram = jf.transpose() * jf;
  // J_fᵀJ_f is zero between groups more than `band` apart.
  double outside = 0.0;
  for (int a = 0; a < blocks.num_groups(); ++a) {
    for (int b = 0; b + blocks.band < a; ++b) {
      outside = std::max(
          outside, gram.block(blocks.group_offset[a], blocks.group_offset[b],
                              blocks.GroupSize(a), blocks.GroupSize(b))
                       .cwiseAbs()
                       .maxCoeff());
    }
  }
  EXPECT_EQ(outside, 0.0);
  std::mt19937 rng(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd v(nf);
  for (Eigen::Index i = 0; i < nf; ++i) v[i] = normal(rng);
  for (const int threads : {1, 2}) {
    SCOPED_TRACE(testing::Message() << threads << " threads");
    structured::StructuredJacobian jacobian(blocks, threads);
    double cost = 0.0;
    ASSERT_TRUE(jacobian.Evaluate(true, &cost));
    structured::SchurElimination schur(blocks, jacobian, threads);
    schur.ComputeGram();
    Eigen::VectorXd d_f, d_p;
    ColumnScaling(jacobian, schur, &d_f, &d_p);
    structured::BandPreconditioner preconditioner(blocks, jacobian, threads);
    for (const double mu : {1e-4, 1.0}) {
      SCOPED_TRACE(testing::Message() << "mu " << mu);
      preconditioner.Build(mu, d_f, schur.grid_grams());
      const Eigen::MatrixXd m = gram + Eigen::MatrixXd(mu * d_f.asDiagonal());
      Eigen::VectorXd applied;
      preconditioner.Apply(v, &applied);
      const Eigen::VectorXd expected = m.ldlt().solve(v);
      EXPECT_LT((applied - expected).norm() / expected.norm(), kBound);
      EXPECT_LT((m * applied - v).norm() / v.norm(), kBound);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, BandPreconditionerOracle, kOracleCases,
                         OracleCaseName);

}  // namespace
}  // namespace nrsfm
