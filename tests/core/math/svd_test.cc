// ComputeTopSvd against the full divide-and-conquer SVD: the same top
// singular values and subspaces on matrices with a planted spectrum (wide,
// tall, small trailing values, a rank-deficient one), and the same bits
// as ComputeThinSvd on small matrices or when most of the spectrum is
// wanted.
#include "core/math/svd.h"

#include <gtest/gtest.h>

#include <Eigen/QR>
#include <random>

namespace nrsfm {
namespace {

// A random m × n matrix U diag(sigma) Vᵀ (orthonormal U, V), plus `noise`
// times a Gaussian matrix.
Eigen::MatrixXd Planted(int m, int n, const Eigen::VectorXd& sigma,
                        double noise, std::mt19937* rng) {
  std::normal_distribution<double> normal;
  const auto gaussian = [&](int rows, int cols) {
    Eigen::MatrixXd g(rows, cols);
    for (Eigen::Index i = 0; i < g.size(); ++i) g.data()[i] = normal(*rng);
    return g;
  };
  const int k = static_cast<int>(sigma.size());
  const Eigen::MatrixXd u =
      Eigen::HouseholderQR<Eigen::MatrixXd>(gaussian(m, k)).householderQ() *
      Eigen::MatrixXd::Identity(m, k);
  const Eigen::MatrixXd v =
      Eigen::HouseholderQR<Eigen::MatrixXd>(gaussian(n, k)).householderQ() *
      Eigen::MatrixXd::Identity(n, k);
  return u * sigma.asDiagonal() * v.transpose() + noise * gaussian(m, n);
}

// The largest principal angle's sine between the column spaces of two
// matrices with orthonormal columns.
double SubspaceGap(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (b - a * (a.transpose() * b)).norm();
}

void ExpectTopSvdMatches(const Eigen::MatrixXd& a, int count,
                         double value_tolerance, double vector_tolerance) {
  const ThinSvd full = ComputeThinSvd(a, SingularVectors::kBoth);
  const ThinSvd top = ComputeTopSvd(a, count, SingularVectors::kBoth);
  ASSERT_EQ(top.singular_values.size(), count);
  ASSERT_EQ(top.u.rows(), a.rows());
  ASSERT_EQ(top.u.cols(), count);
  ASSERT_EQ(top.v.rows(), a.cols());
  ASSERT_EQ(top.v.cols(), count);
  const double sigma1 = full.singular_values(0);
  for (int i = 0; i < count; ++i) {
    EXPECT_NEAR(top.singular_values(i), full.singular_values(i),
                value_tolerance * full.singular_values(i))
        << "singular value " << i;
  }
  // Orthonormal vectors that reproduce A's top part: A v_i = σ_i u_i.
  const Eigen::MatrixXd eye = Eigen::MatrixXd::Identity(count, count);
  EXPECT_LT((top.u.transpose() * top.u - eye).norm(), 1e-12);
  EXPECT_LT((top.v.transpose() * top.v - eye).norm(), 1e-12);
  EXPECT_LT((a * top.v - top.u * top.singular_values.asDiagonal()).norm(),
            1e-12 * sigma1 * count);
  EXPECT_LT(SubspaceGap(full.u.leftCols(count), top.u), vector_tolerance);
  EXPECT_LT(SubspaceGap(full.v.leftCols(count), top.v), vector_tolerance);
  // Only the side asked for.
  const ThinSvd left = ComputeTopSvd(a, count, SingularVectors::kLeft);
  EXPECT_EQ(left.u.cols(), count);
  EXPECT_EQ(left.v.size(), 0);
  const ThinSvd right = ComputeTopSvd(a, count, SingularVectors::kRight);
  EXPECT_EQ(right.u.size(), 0);
  EXPECT_EQ(right.v.cols(), count);
  EXPECT_EQ(right.singular_values, top.singular_values);
}

TEST(TopSvd, MatchesTheFullSvdOnWideAndTallMatrices) {
  std::mt19937 rng(11);
  Eigen::VectorXd sigma(8);
  // A spread of scales down to 1e-7 of the largest (small deformations of a
  // large rigid shape), then a gap to the noise.
  sigma << 1e3, 4e2, 1e2, 3e1, 1.0, 1e-2, 1e-3, 1e-4;
  // 2^20 entries or more: the Gram route.
  const Eigen::MatrixXd wide = Planted(64, 16500, sigma, 1e-9, &rng);
  {
    SCOPED_TRACE("wide");
    ExpectTopSvdMatches(wide, 8, 1e-10, 1e-8);
    ExpectTopSvdMatches(wide, 3, 1e-12, 1e-12);
  }
  {
    SCOPED_TRACE("tall");
    ExpectTopSvdMatches(wide.transpose(), 8, 1e-10, 1e-8);
  }
  // Two counts on one matrix: the same leading values and subspace (not
  // the same bits: the starts' cache keys its SVD by the count), and the
  // values alone.
  const ThinSvd three = ComputeTopSvd(wide, 3, SingularVectors::kBoth);
  const ThinSvd eight = ComputeTopSvd(wide, 8, SingularVectors::kBoth);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(three.singular_values(i), eight.singular_values(i),
                1e-12 * eight.singular_values(i));
  }
  EXPECT_LT(SubspaceGap(eight.u.leftCols(3), three.u), 1e-12);
  const ThinSvd values = ComputeTopSvd(wide, 8, SingularVectors::kNone);
  EXPECT_EQ(values.u.size(), 0);
  EXPECT_EQ(values.v.size(), 0);
  EXPECT_EQ(values.singular_values, eight.singular_values);
}

TEST(TopSvd, RankDeficientMatrixGetsZeroTrailingValues) {
  std::mt19937 rng(12);
  Eigen::VectorXd sigma(3);
  sigma << 5.0, 2.0, 1.0;
  const Eigen::MatrixXd a = Planted(64, 16500, sigma, 0.0, &rng);
  const ThinSvd top = ComputeTopSvd(a, 6, SingularVectors::kBoth);
  EXPECT_NEAR(top.singular_values(0), 5.0, 1e-12);
  EXPECT_NEAR(top.singular_values(2), 1.0, 1e-12);
  for (int i = 3; i < 6; ++i) EXPECT_LT(top.singular_values(i), 1e-12);
  EXPECT_LT(
      (top.u.transpose() * top.u - Eigen::MatrixXd::Identity(6, 6)).norm(),
      1e-12);
}

TEST(TopSvd, IsTheFullSvdForSmallMatricesOrMostOfTheSpectrum) {
  std::mt19937 rng(13);
  Eigen::VectorXd sigma(5);
  sigma << 9.0, 7.0, 3.0, 2.0, 1.0;
  const Eigen::MatrixXd a = Planted(30, 20, sigma, 1e-3, &rng);
  const ThinSvd full = ComputeThinSvd(a, SingularVectors::kBoth);
  const ThinSvd top = ComputeTopSvd(a, 6, SingularVectors::kBoth);  // 24 > 20
  EXPECT_EQ(top.singular_values, full.singular_values.head(6));
  EXPECT_EQ(top.u, full.u.leftCols(6));
  EXPECT_EQ(top.v, full.v.leftCols(6));
  // A large matrix of which more than a quarter of the spectrum is wanted.
  Eigen::VectorXd many(20);
  for (int i = 0; i < 20; ++i) many(i) = 100.0 / (1 + i);
  const Eigen::MatrixXd large = Planted(64, 16500, many, 1e-6, &rng);
  const ThinSvd large_full = ComputeThinSvd(large, SingularVectors::kBoth);
  const ThinSvd large_top = ComputeTopSvd(large, 17, SingularVectors::kBoth);
  EXPECT_EQ(large_top.singular_values, large_full.singular_values.head(17));
  EXPECT_EQ(large_top.u, large_full.u.leftCols(17));
  EXPECT_EQ(large_top.v, large_full.v.leftCols(17));
  // A small matrix, however few values are wanted.
  const ThinSvd few = ComputeTopSvd(a, 2, SingularVectors::kBoth);
  EXPECT_EQ(few.u, full.u.leftCols(2));
  EXPECT_EQ(few.v, full.v.leftCols(2));
}

}  // namespace
}  // namespace nrsfm
