#include "core/svd.h"

#include <Eigen/SVD>

namespace nrsfm {
namespace {

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

ThinSvd ComputeJacobiSvd(const Eigen::MatrixXd& a, SingularVectors vectors) {
  return Collect(Eigen::JacobiSVD<Eigen::MatrixXd>(a, Options(vectors)),
                 vectors);
}

}  // namespace nrsfm
