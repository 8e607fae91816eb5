// SchurElimination (solvers/refine/schur_elimination.h) against the dense
// Schur complement formed from Ceres' own Jacobian of the same problem
// (tests/solvers/refine/dense_oracle.h): J = [J_f J_p], C̃ = J_pᵀJ_p + μD_p,
// S = J_fᵀJ_f + μD_f − J_fᵀJ_p C̃⁻¹ J_pᵀJ_f, and the step of the whole
// Levenberg–Marquardt system (JᵀJ + μD) δ = −Jᵀr from the reduced one.
#include "solvers/refine/schur_elimination.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <random>

#include "solvers/refine/structured_jacobian.h"
#include "tests/solvers/refine/dense_oracle.h"

namespace nrsfm {
namespace {

double RelativeDifference(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).norm() / b.norm();
}

// Measured (this test, both cases, μ 1e-4 and 1, 1 and 2 threads alike):
// C̃⁻¹e, S v and the right-hand side within 2.0e-12 of the dense values
// (C̃⁻¹e of the two cameras at μ 1e-4; the rest 5e-15 at most); the step
// within 1.7e-12 (the same case), 5.3e-14 with coupled points; the
// gradient within 3.3e-16.
constexpr double kBound = 1e-11;

class SchurEliminationOracle : public testing::TestWithParam<OracleCase> {};

TEST_P(SchurEliminationOracle, IsTheDenseSchurComplement) {
  const std::unique_ptr<OracleProblem> p = MakeOracleProblem(GetParam());
  const structured::StructuredBlocks& blocks = p->blocks;
  const int nf = blocks.num_reduced, np = blocks.num_eliminated;
  ASSERT_GT(nf, 0);
  ASSERT_GT(np, 0);
  const DenseJacobian dense = EvaluateDense(blocks, p->builder->problem());
  const Eigen::MatrixXd jf = dense.jacobian.leftCols(nf);
  const Eigen::MatrixXd jp = dense.jacobian.rightCols(np);
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd v(nf), e(np);
  for (Eigen::Index i = 0; i < nf; ++i) v[i] = normal(rng);
  for (Eigen::Index i = 0; i < np; ++i) e[i] = normal(rng);
  for (const int threads : {1, 2}) {
    SCOPED_TRACE(testing::Message() << threads << " threads");
    structured::StructuredJacobian jacobian(blocks, threads);
    double cost = 0.0;
    ASSERT_TRUE(jacobian.Evaluate(true, &cost));
    EXPECT_NEAR(cost, dense.cost, 1e-12 * dense.cost);
    structured::SchurElimination schur(blocks, jacobian, threads);
    schur.ComputeGram();
    // The gradient and D as the solver forms them (structured_solver.cc).
    Eigen::VectorXd g_f, g_p, d_f, d_p;
    jacobian.Gradient(&g_f, &g_p);
    ColumnScaling(jacobian, schur, &d_f, &d_p);
    const Eigen::VectorXd gradient =
        dense.jacobian.transpose() * dense.residuals;
    EXPECT_LT(RelativeDifference(g_f, gradient.head(nf)), 1e-14);
    EXPECT_LT(RelativeDifference(g_p, gradient.tail(np)), 1e-14);
    for (const double mu : {1e-4, 1.0}) {
      SCOPED_TRACE(testing::Message() << "mu " << mu);
      schur.Factor(mu, d_p);
      const Eigen::MatrixXd c =
          jp.transpose() * jp + Eigen::MatrixXd(mu * d_p.asDiagonal());
      const Eigen::LDLT<Eigen::MatrixXd> c_ldlt(c);
      const Eigen::MatrixXd coupling = jf.transpose() * jp;  // J_fᵀJ_p
      const Eigen::MatrixXd s = jf.transpose() * jf +
                                Eigen::MatrixXd(mu * d_f.asDiagonal()) -
                                coupling * c_ldlt.solve(coupling.transpose());
      // C̃⁻¹ e.
      Eigen::VectorXd solved;
      schur.SolveEliminated(e, &solved);
      EXPECT_LT(RelativeDifference(solved, c_ldlt.solve(e)), kBound);
      // S v.
      Eigen::VectorXd sv;
      schur.ApplyReduced(v, mu, d_f, &sv);
      EXPECT_LT(RelativeDifference(sv, s * v), kBound);
      // The reduced right-hand side −g_f + J_fᵀJ_p C̃⁻¹ g_p.
      Eigen::VectorXd rhs;
      schur.ReducedRightHandSide(g_f, g_p, &rhs);
      const Eigen::VectorXd expected_rhs =
          -gradient.head(nf) + coupling * c_ldlt.solve(gradient.tail(np));
      EXPECT_LT(RelativeDifference(rhs, expected_rhs), kBound);
      // The reduced system's solution, back-substituted, is the step of the
      // whole system.
      const Eigen::VectorXd step_f = s.ldlt().solve(expected_rhs);
      Eigen::VectorXd step_p;
      schur.BackSubstitute(step_f, g_p, &step_p);
      Eigen::VectorXd step(nf + np), d(nf + np);
      step << step_f, step_p;
      d << d_f, d_p;
      const Eigen::MatrixXd whole =
          dense.jacobian.transpose() * dense.jacobian +
          Eigen::MatrixXd(mu * d.asDiagonal());
      const Eigen::VectorXd expected_step = whole.ldlt().solve(-gradient);
      EXPECT_LT(RelativeDifference(step, expected_step), kBound);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, SchurEliminationOracle, kOracleCases,
                         OracleCaseName);

}  // namespace
}  // namespace nrsfm
