#include "core/math/svd.h"

#include <glog/logging.h>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>

namespace nrsfm {
namespace {

// ComputeTopSvd takes the full SVD below this many entries (where it costs
// well under a second: the Gram route is for speed only), and makes this
// many subspace iterations after the Gram matrix's eigenvectors.
constexpr Eigen::Index kTopSvdMinEntries = 1 << 20;
constexpr int kTopSvdIterations = 2;

unsigned int Options(SingularVectors vectors) {
  switch (vectors) {
    case SingularVectors::kNone:
      return 0;
    case SingularVectors::kLeft:
      return Eigen::ComputeThinU;
    case SingularVectors::kRight:
      return Eigen::ComputeThinV;
    case SingularVectors::kBoth:
      return Eigen::ComputeThinU | Eigen::ComputeThinV;
  }
  return 0;
}

template <typename Svd>
ThinSvd Collect(const Svd& svd, SingularVectors vectors) {
  ThinSvd result;
  result.singular_values = svd.singularValues();
  if (vectors == SingularVectors::kLeft || vectors == SingularVectors::kBoth) {
    result.u = svd.matrixU();
  }
  if (vectors == SingularVectors::kRight || vectors == SingularVectors::kBoth) {
    result.v = svd.matrixV();
  }
  return result;
}

}  // namespace

ThinSvd ComputeThinSvd(const Eigen::MatrixXd& a, SingularVectors vectors) {
  return Collect(Eigen::BDCSVD<Eigen::MatrixXd>(a, Options(vectors)), vectors);
}

ThinSvd ComputeTopSvd(const Eigen::MatrixXd& a, int count,
                      SingularVectors vectors) {
  const Eigen::Index short_side = std::min(a.rows(), a.cols());
  CHECK_GE(count, 1);
  CHECK_LE(count, short_side);
  const bool want_u =
      vectors == SingularVectors::kLeft || vectors == SingularVectors::kBoth;
  const bool want_v =
      vectors == SingularVectors::kRight || vectors == SingularVectors::kBoth;
  if (4 * static_cast<Eigen::Index>(count) > short_side ||
      a.size() < kTopSvdMinEntries) {
    ThinSvd svd = ComputeThinSvd(a, vectors);
    svd.singular_values = svd.singular_values.head(count).eval();
    if (want_u) svd.u = svd.u.leftCols(count).eval();
    if (want_v) svd.v = svd.v.leftCols(count).eval();
    return svd;
  }
  // Work on the short side: s = A (wide) or Aᵀ (tall), so that s sᵀ is
  // short_side × short_side and the top left singular vectors of s are the
  // wanted side's.
  const bool wide = a.rows() <= a.cols();
  const Eigen::MatrixXd transposed = wide ? Eigen::MatrixXd() : a.transpose();
  const Eigen::MatrixXd& s = wide ? a : transposed;
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(short_side, short_side);
  gram.selfadjointView<Eigen::Lower>().rankUpdate(s);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram);
  // Eigenvalues ascending: the last `count` columns, largest first.
  Eigen::MatrixXd q =
      eigen.eigenvectors().rightCols(count).rowwise().reverse().eval();
  // Subspace iterations with s itself, each followed by an orthonormal
  // basis.
  for (int iteration = 0; iteration < kTopSvdIterations; ++iteration) {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(s * (s.transpose() * q));
    q = qr.householderQ() * Eigen::MatrixXd::Identity(short_side, count);
  }
  // Rayleigh-Ritz: s ≈ q (qᵀ s), and qᵀ s = W Σ Zᵀ is count × long side.
  const Eigen::BDCSVD<Eigen::MatrixXd> small(
      q.transpose() * s, Eigen::ComputeThinU | Eigen::ComputeThinV);
  ThinSvd svd;
  svd.singular_values = small.singularValues();
  const bool want_short = wide ? want_u : want_v;
  const bool want_long = wide ? want_v : want_u;
  Eigen::MatrixXd short_vectors, long_vectors;
  if (want_short) short_vectors = q * small.matrixU();
  if (want_long) long_vectors = small.matrixV();
  svd.u = wide ? short_vectors : long_vectors;
  svd.v = wide ? long_vectors : short_vectors;
  return svd;
}

ThinSvd ComputeJacobiSvd(const Eigen::MatrixXd& a, SingularVectors vectors) {
  return Collect(Eigen::JacobiSVD<Eigen::MatrixXd>(a, Options(vectors)),
                 vectors);
}

}  // namespace nrsfm
