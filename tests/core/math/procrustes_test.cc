#include "core/math/procrustes.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <vector>

#include "core/math/rotation.h"

namespace nrsfm {
namespace {

// A fixed, non-degenerate 3 × 6 point set (no symmetry, not planar).
Eigen::Matrix3Xd Points() {
  Eigen::Matrix3Xd x(3, 6);
  x << 0.3, -1.1, 0.7, 2.0, -0.4, 0.1,  //
      1.2, 0.5, -0.9, 0.3, -1.5, 0.8,   //
      -0.6, 0.9, 0.4, -1.2, 0.2, 1.7;
  return x;
}

const Eigen::Matrix3d kReflectZ = Eigen::Vector3d(1, 1, -1).asDiagonal();

TEST(Procrustes, RecoversAKnownRotation) {
  const Eigen::Matrix3d r =
      AngleAxisToRotation(Eigen::Vector3d(0.4, -1.3, 2.2));
  const Eigen::Matrix3Xd source = Points();
  const Eigen::Matrix3Xd target = r * source;
  for (bool allow_reflection : {false, true}) {
    EXPECT_LT((AlignOrthogonal(target, source, allow_reflection) - r).norm(),
              1e-12);
  }
}

TEST(Procrustes, RecoversAReflectionOnlyWhenAllowed) {
  const Eigen::Matrix3d r =
      AngleAxisToRotation(Eigen::Vector3d(-0.7, 0.2, 0.9));
  const Eigen::Matrix3d q = r * kReflectZ;  // det −1
  const Eigen::Matrix3Xd source = Points();
  const Eigen::Matrix3Xd target = q * source;
  const Eigen::Matrix3d with = AlignOrthogonal(target, source, true);
  EXPECT_LT((with - q).norm(), 1e-12);
  EXPECT_NEAR(with.determinant(), -1.0, 1e-12);
  // Restricted to rotations the fit is a proper rotation that cannot be exact.
  const Eigen::Matrix3d without = AlignOrthogonal(target, source, false);
  EXPECT_NEAR(without.determinant(), 1.0, 1e-12);
  EXPECT_LT(
      (without * without.transpose() - Eigen::Matrix3d::Identity()).norm(),
      1e-12);
  EXPECT_GT((target - without * source).norm(), 0.1);
}

TEST(Procrustes, NearestOrthogonalOfAScaledOrthogonalMatrixIsItself) {
  const Eigen::Matrix3d q =
      AngleAxisToRotation(Eigen::Vector3d(0.1, 0.2, 0.3)) * kReflectZ;
  EXPECT_LT((NearestOrthogonal(2.5 * q) - q).norm(), 1e-12);
  EXPECT_LT((OrthogonalFromCrossCovariance(2.5 * q, true) - q).norm(), 1e-12);
  EXPECT_NEAR(OrthogonalFromCrossCovariance(2.5 * q, false).determinant(), 1.0,
              1e-12);
}

TEST(Procrustes, MultiFrameFitRecoversOneRotationForAllFrames) {
  const Eigen::Matrix3d r =
      AngleAxisToRotation(Eigen::Vector3d(1.0, 0.5, -0.25));
  std::vector<Eigen::Matrix3Xd> source, target;
  for (int t = 0; t < 3; ++t) {
    // Each frame alone is a different shape; one rotation maps all of them.
    source.push_back(Points() + 0.3 * t * Eigen::Matrix3Xd::Ones(3, 6));
    target.push_back(r * source.back());
  }
  EXPECT_LT((AlignOrthogonal(target, source, false) - r).norm(), 1e-12);
  EXPECT_LT((AlignLeastSquaresThenOrthogonal(target, source) - r).norm(),
            1e-12);
  // A reflection is recovered by the least-squares fit as well.
  for (Eigen::Matrix3Xd& x : target) x = kReflectZ * x;
  EXPECT_LT(
      (AlignLeastSquaresThenOrthogonal(target, source) - kReflectZ * r).norm(),
      1e-12);
}

TEST(Procrustes,
     LeastSquaresThenOrthogonalDiffersFromProcrustesOnAnisotropicData) {
  // source = D R target with D = diag(2, 1, 1): the least-squares linear map
  // is exact, A = (D R)⁻¹, so the e3D alignment is NearestOrthogonal(A);
  // orthogonal Procrustes gives another matrix with a smaller squared error.
  const Eigen::Matrix3Xd target = Points();
  const Eigen::Matrix3d r = AngleAxisToRotation(Eigen::Vector3d(0.3, 0.0, 0.8));
  const Eigen::Matrix3Xd source =
      Eigen::Vector3d(2.0, 1.0, 1.0).asDiagonal() * r * target;
  const Eigen::Matrix3d a =
      (Eigen::Vector3d(2.0, 1.0, 1.0).asDiagonal() * r).inverse();
  const Eigen::Matrix3d expected = NearestOrthogonal(a);
  const Eigen::Matrix3d fit =
      AlignLeastSquaresThenOrthogonal({target}, {source});
  EXPECT_LT((fit - expected).norm(), 1e-12);
  const Eigen::Matrix3d procrustes = AlignOrthogonal(target, source, true);
  EXPECT_GT((fit - procrustes).norm(), 1e-3);
  // Procrustes has the smaller squared residual, as it must.
  EXPECT_LT((target - procrustes * source).squaredNorm(),
            (target - fit * source).squaredNorm());
}

TEST(Procrustes, LeastSquaresThenOrthogonalHandlesAFlatSource) {
  // z = 0 in the source (a flat reconstruction): M is singular, M⁺ keeps the
  // fit finite and it still maps x and y correctly.
  Eigen::Matrix3Xd target = Points();
  target.row(2).setZero();
  const Eigen::Matrix3d r = AngleAxisToRotation(Eigen::Vector3d(0.0, 0.0, 0.6));
  const Eigen::Matrix3Xd source = r.transpose() * target;
  const Eigen::Matrix3d fit =
      AlignLeastSquaresThenOrthogonal({target}, {source});
  ASSERT_TRUE(fit.allFinite());
  EXPECT_LT((fit * fit.transpose() - Eigen::Matrix3d::Identity()).norm(),
            1e-12);
  EXPECT_LT((target - fit * source).norm(), 1e-12);
}

TEST(Procrustes, SimilarityRecoversScaleRotationAndTranslation) {
  const Eigen::Matrix3d r =
      AngleAxisToRotation(Eigen::Vector3d(-0.2, 0.9, 0.4));
  const Eigen::Vector3d shift(1.0, -2.0, 0.5);
  const Eigen::Matrix3Xd source = Points();
  const Eigen::Matrix3Xd target = ((1.7 * r) * source).colwise() + shift;
  SimilarityTransform s = AlignSimilarity(target, source, true, false);
  EXPECT_NEAR(s.scale, 1.7, 1e-12);
  EXPECT_LT((s.rotation - r).norm(), 1e-12);
  EXPECT_LT((s.translation - shift).norm(), 1e-12);
  EXPECT_LT((s.Apply(source) - target).norm(), 1e-11);

  // With a reflection in the data, only allow_reflection fits exactly.
  const Eigen::Matrix3Xd reflected =
      ((1.7 * r * kReflectZ) * source).colwise() + shift;
  s = AlignSimilarity(reflected, source, true, true);
  EXPECT_NEAR(s.scale, 1.7, 1e-12);
  EXPECT_LT((s.rotation - r * kReflectZ).norm(), 1e-12);
  EXPECT_LT((s.Apply(source) - reflected).norm(), 1e-11);
  s = AlignSimilarity(reflected, source, true, false);
  EXPECT_NEAR(s.rotation.determinant(), 1.0, 1e-12);
  EXPECT_GT((s.Apply(source) - reflected).norm(), 0.1);

  // Without scaling the scale stays 1 and the rotation is still recovered.
  const Eigen::Matrix3Xd rigid = (r * source).colwise() + shift;
  for (bool allow_reflection : {false, true}) {
    s = AlignSimilarity(rigid, source, false, allow_reflection);
    EXPECT_EQ(s.scale, 1.0);
    EXPECT_LT((s.rotation - r).norm(), 1e-12);
    EXPECT_LT((s.translation - shift).norm(), 1e-12);
  }
}

}  // namespace
}  // namespace nrsfm
