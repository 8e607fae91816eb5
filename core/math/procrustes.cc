#include "core/math/procrustes.h"

#include <glog/logging.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <limits>

#include "core/math/rotation.h"

namespace nrsfm {
namespace {

// Σ_t target_t source_tᵀ after checking the sizes.
Eigen::Matrix3d CrossCovariance(const std::vector<Eigen::Matrix3Xd>& target,
                                const std::vector<Eigen::Matrix3Xd>& source) {
  CHECK_EQ(target.size(), source.size());
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  for (size_t t = 0; t < target.size(); ++t) {
    CHECK_EQ(target[t].cols(), source[t].cols()) << "frame " << t;
    c.noalias() += target[t] * source[t].transpose();
  }
  return c;
}

}  // namespace

Eigen::Matrix3d NearestOrthogonal(const Eigen::Matrix3d& m) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(
      m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return svd.matrixU() * svd.matrixV().transpose();
}

Eigen::Matrix3d OrthogonalFromCrossCovariance(
    const Eigen::Matrix3d& cross_covariance, bool allow_reflection) {
  return allow_reflection ? NearestOrthogonal(cross_covariance)
                          : NearestRotation(cross_covariance);
}

Eigen::Matrix3d AlignOrthogonal(const Eigen::Matrix3Xd& target,
                                const Eigen::Matrix3Xd& source,
                                bool allow_reflection) {
  CHECK_EQ(target.cols(), source.cols());
  return OrthogonalFromCrossCovariance(target * source.transpose(),
                                       allow_reflection);
}

Eigen::Matrix3d AlignOrthogonal(const std::vector<Eigen::Matrix3Xd>& target,
                                const std::vector<Eigen::Matrix3Xd>& source,
                                bool allow_reflection) {
  return OrthogonalFromCrossCovariance(CrossCovariance(target, source),
                                       allow_reflection);
}

Eigen::Matrix3d AlignLeastSquaresThenOrthogonal(
    const std::vector<Eigen::Matrix3Xd>& target,
    const std::vector<Eigen::Matrix3Xd>& source) {
  const Eigen::Matrix3d c = CrossCovariance(target, source);
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (const Eigen::Matrix3Xd& x : source) m.noalias() += x * x.transpose();
  // M⁺ from the eigen-decomposition of the symmetric M, dropping eigenvalues
  // below MATLAB pinv's tolerance (3 · eps · largest).
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(m);
  const Eigen::Vector3d values = eigen.eigenvalues();
  const double tolerance = 3.0 * std::numeric_limits<double>::epsilon() *
                           values.cwiseAbs().maxCoeff();
  Eigen::Vector3d inverse_values = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i) {
    if (values(i) > tolerance) inverse_values(i) = 1.0 / values(i);
  }
  const Eigen::Matrix3d m_pinv = eigen.eigenvectors() *
                                 inverse_values.asDiagonal() *
                                 eigen.eigenvectors().transpose();
  return NearestOrthogonal(c * m_pinv);
}

Eigen::Matrix3Xd SimilarityTransform::Apply(
    const Eigen::Matrix3Xd& points) const {
  return ((scale * rotation) * points).colwise() + translation;
}

SimilarityTransform AlignSimilarity(const Eigen::Matrix3Xd& target,
                                    const Eigen::Matrix3Xd& source,
                                    bool with_scaling, bool allow_reflection) {
  CHECK_EQ(target.cols(), source.cols());
  CHECK_GE(source.cols(), 1);
  const Eigen::Vector3d source_mean = source.rowwise().mean();
  const Eigen::Vector3d target_mean = target.rowwise().mean();
  const Eigen::Matrix3Xd x = source.colwise() - source_mean;
  const Eigen::Matrix3Xd y = target.colwise() - target_mean;
  const double source_spread = x.squaredNorm();
  if (with_scaling)
    CHECK_GT(source_spread, 0.0) << "all source points coincide";
  SimilarityTransform result;
  if (!allow_reflection) {
    const Eigen::Matrix4d t = Eigen::umeyama(source, target, with_scaling);
    result.scale = with_scaling ? t.topLeftCorner<3, 3>().col(0).norm() : 1.0;
    result.rotation = t.topLeftCorner<3, 3>() / result.scale;
    result.translation = t.topRightCorner<3, 1>();
    return result;
  }
  // Umeyama's closed form without the det = +1 correction (D = I).
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(
      y * x.transpose(), Eigen::ComputeFullU | Eigen::ComputeFullV);
  result.rotation = svd.matrixU() * svd.matrixV().transpose();
  if (with_scaling) result.scale = svd.singularValues().sum() / source_spread;
  result.translation =
      target_mean - result.scale * result.rotation * source_mean;
  return result;
}

}  // namespace nrsfm
