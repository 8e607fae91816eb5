// FitWeightsGivenBasis (solvers/start/basis_weight_fit.h) against the normal
// equations of each frame's design matrix formed row by row: frames that see
// most points (the sums over all points less the hidden ones), frames that
// see few (the seen ones summed), a frame that sees none; with and without
// the translations; the same bits for 1 and 3 threads.
#include "solvers/start/basis_weight_fit.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <random>

namespace nrsfm {
namespace {

// The reference: A (2·seen × n) row by row, (AᵀA + λ tr/n I) x = Aᵀ w̃;
// `condition` the 2-norm condition number of the damped AᵀA.
Eigen::VectorXd ReferenceFit(const Measurements& m, const Model& model, int t,
                             double damping, bool fit_translations,
                             double* condition) {
  const int k = model.num_bases;
  const int n = k + (fit_translations ? 2 : 0);
  const Eigen::Matrix<double, 2, 3> pr = model.Rotation(t, 0).topRows<2>();
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
  for (int p = 0; p < m.num_points; ++p) {
    if (!m.visible(t, p)) continue;
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2, n);
    for (int b = 0; b < k; ++b)
      a.col(b) = pr * model.basis.block<3, 1>(3 * b, p);
    if (fit_translations) a.rightCols<2>().setIdentity();
    const Eigen::Vector2d w =
        m.Observation(t, 0, p) -
        (fit_translations ? Eigen::Vector2d::Zero()
                          : Eigen::Vector2d(model.translations.col(t)));
    normal += a.transpose() * a;
    rhs += a.transpose() * w;
  }
  const double trace = normal.trace();
  normal.diagonal().array() +=
      damping * (trace > 0.0 ? trace / n : 1.0) + 1e-300;
  const Eigen::VectorXd eigenvalues =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(normal).eigenvalues();
  *condition = eigenvalues.maxCoeff() / eigenvalues.minCoeff();
  return normal.ldlt().solve(rhs);
}

TEST(FitWeightsGivenBasis, EqualsTheNormalEquationsOfEachFrame) {
  const int f = 12, p = 30, k = 3;
  std::mt19937 rng(4);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Measurements m;
  m.num_frames = f;
  m.num_points = p;
  m.W.resize(2 * f, p);
  m.visible.resize(f, p);
  for (int t = 0; t < f; ++t) {
    // Frames 0-5 see ~90 % of the points, 6-10 ~20 %, frame 11 none.
    const double seen = t < 6 ? 0.9 : (t < 11 ? 0.2 : 0.0);
    for (int q = 0; q < p; ++q) {
      m.visible(t, q) = uniform(rng) < seen;
      m.W(2 * t, q) = normal(rng);
      m.W(2 * t + 1, q) = normal(rng);
    }
  }
  Model start;
  start.Resize(f, 1, p, k);
  for (int t = 0; t < f; ++t) {
    const Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng),
                               normal(rng));
    start.SetRotation(t, 0, q.normalized().toRotationMatrix());
    start.translations.col(t) = Eigen::Vector2d(normal(rng), normal(rng));
  }
  for (Eigen::Index i = 0; i < start.basis.size(); ++i)
    start.basis.data()[i] = 3.0 + normal(rng);  // far from the origin
  const double damping = 1e-9;
  for (const bool fit_translations : {true, false}) {
    SCOPED_TRACE(fit_translations ? "with translations" : "weights only");
    Model one = start, three = start;
    FitWeightsGivenBasis(m, damping, fit_translations, &one, 1);
    FitWeightsGivenBasis(m, damping, fit_translations, &three, 3);
    EXPECT_EQ(one.weights, three.weights);
    EXPECT_EQ(one.translations, three.translations);
    for (int t = 0; t < f; ++t) {
      SCOPED_TRACE(t);
      double condition = 0.0;
      const Eigen::VectorXd expected =
          ReferenceFit(m, start, t, damping, fit_translations, &condition);
      // Both solve normal equations summed in another order: they agree to
      // round-off times the condition number.
      const double tolerance = 1e-14 * condition * (1.0 + expected.norm());
      ASSERT_LT(tolerance, 1e-3);
      EXPECT_LT((one.weights.col(t) - expected.head(k)).norm(), tolerance)
          << "condition " << condition;
      if (fit_translations) {
        EXPECT_LT((one.translations.col(t) - expected.tail<2>()).norm(),
                  tolerance);
      } else {
        EXPECT_EQ(one.translations.col(t), start.translations.col(t));
      }
    }
  }
}

}  // namespace
}  // namespace nrsfm
