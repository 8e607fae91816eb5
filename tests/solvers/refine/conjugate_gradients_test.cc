// ConjugateGradients (solvers/refine/conjugate_gradients.h) against dense
// solves of the same random symmetric positive definite systems: the
// converged solution against Eigen's LDLT, and each early iterate against
// the one preconditioned CG defines, the minimiser of the A-norm error over
// the Krylov space of M⁻¹A and M⁻¹b (computed densely).
#include "solvers/refine/conjugate_gradients.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <cmath>
#include <random>

namespace nrsfm {
namespace {

using structured::ConjugateGradients;
using structured::ConjugateGradientsOptions;
using structured::LinearOperator;

// A = S Qᵀ diag(e) Q S with eigenvalues e from 1 to `condition` (Q a
// random orthogonal matrix) and a random diagonal scaling S (0.5 … 2), which
// a Jacobi preconditioner undoes in part; b random.
struct System {
  Eigen::MatrixXd a;
  Eigen::VectorXd b;
};

System RandomSystem(int n, double condition, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Eigen::MatrixXd g(n, n);
  for (Eigen::Index i = 0; i < g.size(); ++i) g.data()[i] = normal(rng);
  const Eigen::MatrixXd q =
      Eigen::HouseholderQR<Eigen::MatrixXd>(g).householderQ();
  Eigen::VectorXd e(n), scale(n);
  for (int i = 0; i < n; ++i) {
    e[i] = std::pow(condition, static_cast<double>(i) / (n - 1));
    scale[i] = std::pow(2.0, 2.0 * uniform(rng) - 1.0);  // 0.5 … 2
  }
  System s;
  s.a = scale.asDiagonal() * (q.transpose() * e.asDiagonal() * q) *
        scale.asDiagonal();
  s.b.resize(n);
  for (int i = 0; i < n; ++i) s.b[i] = normal(rng);
  return s;
}

// out = a in (a copy of `a`).
LinearOperator Multiply(const Eigen::MatrixXd& a) {
  return
      [a](const Eigen::VectorXd& in, Eigen::VectorXd* out) { *out = a * in; };
}

// The k-th iterate of CG from x = 0 with preconditioner M⁻¹ = `m_inverse`:
// argmin over x in span{M⁻¹b, (M⁻¹A) M⁻¹b, …} (k vectors) of
// (x − x*)ᵀ A (x − x*), i.e. x = V (VᵀAV)⁻¹ Vᵀ b for an orthonormal basis V
// of that space (Arnoldi: each new vector M⁻¹A v_j orthogonalised twice
// against the others).
Eigen::VectorXd KrylovIterate(const Eigen::MatrixXd& a,
                              const Eigen::MatrixXd& m_inverse,
                              const Eigen::VectorXd& b, int k) {
  Eigen::MatrixXd basis(b.size(), k);
  Eigen::VectorXd v = m_inverse * b;
  for (int j = 0; j < k; ++j) {
    for (int pass = 0; pass < 2; ++pass) {
      v -= basis.leftCols(j) * (basis.leftCols(j).transpose() * v);
    }
    basis.col(j) = v / v.norm();
    v = m_inverse * (a * basis.col(j));
  }
  const Eigen::MatrixXd projected = basis.transpose() * a * basis;
  return basis * projected.ldlt().solve(basis.transpose() * b);
}

TEST(ConjugateGradients, ConvergesToTheDenseSolution) {
  const System s = RandomSystem(60, 1e4, 1);
  const Eigen::VectorXd exact = s.a.ldlt().solve(s.b);
  const Eigen::VectorXd jacobi = s.a.diagonal().cwiseInverse();
  const LinearOperator identity = [](const Eigen::VectorXd& in,
                                     Eigen::VectorXd* out) { *out = in; };
  const LinearOperator diagonal = [&jacobi](const Eigen::VectorXd& in,
                                            Eigen::VectorXd* out) {
    *out = jacobi.cwiseProduct(in);
  };
  ConjugateGradientsOptions options;
  options.relative_tolerance = 1e-12;
  options.max_iterations = 1000;
  for (const bool preconditioned : {false, true}) {
    SCOPED_TRACE(preconditioned ? "Jacobi" : "no preconditioner");
    Eigen::VectorXd x;
    const int iterations = ConjugateGradients(
        options, Multiply(s.a), preconditioned ? diagonal : identity, s.b, &x);
    // Measured (this test): 160 iterations without and 129 with the
    // preconditioner for n = 60 at condition 1e4 (round-off makes it more
    // than n); the error 4.1e-11 and 1.9e-11 of ||x*|| (the recurrence's
    // residual 1e-12 of ||b||, times the condition number at most).
    // Measured (this test): 245 iterations without and 209 with the
    // preconditioner for n = 60 at condition ~1.6e4 (round-off makes it
    // more than n); the bound about 1.2 times that.
    EXPECT_LE(iterations, preconditioned ? 250 : 295);
    // Measured: 1.0e-13 and 7.5e-14 of ||x*||.
    EXPECT_LT((x - exact).norm() / exact.norm(), 1e-12);
    // The recurrence's residual is the true one up to round-off:
    // ||b − A x|| measured 1.02e-12 and 5.9e-13 of ||b|| (the recurrence's
    // ≤ 1e-12).
    EXPECT_LT((s.b - s.a * x).norm() / s.b.norm(), 2e-12);
  }
}

TEST(ConjugateGradients, EachIterateMinimisesTheErrorOverItsKrylovSpace) {
  const System s = RandomSystem(40, 1e3, 2);
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(40, 40);
  const Eigen::MatrixXd jacobi = s.a.diagonal().cwiseInverse().asDiagonal();
  ConjugateGradientsOptions options;
  options.relative_tolerance = 0.0;  // stop at max_iterations only
  for (const Eigen::MatrixXd* m : {&identity, &jacobi}) {
    const LinearOperator preconditioner = Multiply(*m);
    for (const int k : {1, 2, 5, 10}) {
      SCOPED_TRACE(testing::Message()
                   << (m == &identity ? "I" : "Jacobi") << ", k " << k);
      options.max_iterations = k;
      Eigen::VectorXd x;
      EXPECT_EQ(
          ConjugateGradients(options, Multiply(s.a), preconditioner, s.b, &x),
          k);
      const Eigen::VectorXd expected = KrylovIterate(s.a, *m, s.b, k);
      // Measured (this test): at most 2.0e-14 of ||x_k|| over the eight
      // cases (round-off of both computations).
      EXPECT_LT((x - expected).norm() / expected.norm(), 1e-13);
    }
  }
}

// The first iterate whose residual is within the tolerance: the one before
// is not (each iterate from a run that stops only at max_iterations).
TEST(ConjugateGradients, StopsAtTheFirstIterateWithinTheTolerance) {
  const System s = RandomSystem(40, 1e3, 3);
  const LinearOperator identity = Multiply(Eigen::MatrixXd::Identity(40, 40));
  const auto relative_residual = [&s](const Eigen::VectorXd& y) {
    return (s.b - s.a * y).norm() / s.b.norm();
  };
  ConjugateGradientsOptions options;
  options.relative_tolerance = 0.1;
  Eigen::VectorXd x;
  const int k = ConjugateGradients(options, Multiply(s.a), identity, s.b, &x);
  ASSERT_GE(k, 2);  // measured: 30
  EXPECT_LE(relative_residual(x), 0.1);
  options.relative_tolerance = 0.0;
  options.max_iterations = k - 1;
  Eigen::VectorXd before, same;
  EXPECT_EQ(ConjugateGradients(options, Multiply(s.a), identity, s.b, &before),
            k - 1);
  EXPECT_GT(relative_residual(before), 0.1);
  options.max_iterations = k;
  ConjugateGradients(options, Multiply(s.a), identity, s.b, &same);
  EXPECT_EQ(same, x);
}

TEST(ConjugateGradients, StopsWhereTheOperatorIsNotPositive) {
  // A = 0: pᵀ A p = 0 at once, no step, x stays 0.
  const Eigen::MatrixXd zero = Eigen::MatrixXd::Zero(5, 5);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(5);
  Eigen::VectorXd x;
  EXPECT_EQ(
      ConjugateGradients({}, Multiply(zero),
                         Multiply(Eigen::MatrixXd::Identity(5, 5)), b, &x),
      0);
  EXPECT_EQ(x, Eigen::VectorXd::Zero(5));
  // b = 0: nothing to do.
  const System s = RandomSystem(5, 10.0, 4);
  EXPECT_EQ(ConjugateGradients({}, Multiply(s.a),
                               Multiply(Eigen::MatrixXd::Identity(5, 5)),
                               Eigen::VectorXd::Zero(5), &x),
            0);
  EXPECT_EQ(x, Eigen::VectorXd::Zero(5));
}

}  // namespace
}  // namespace nrsfm
