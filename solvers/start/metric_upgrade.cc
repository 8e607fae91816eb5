#include "solvers/start/metric_upgrade.h"

#include <glog/logging.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/math/svd.h"

namespace nrsfm {
namespace {

// Coefficients of aᵀ H b in h = (H00, H01, H02, H11, H12, H22).
Eigen::Matrix<double, 1, 6> BilinearRow(const Eigen::RowVector3d& a,
                                        const Eigen::RowVector3d& b) {
  Eigen::Matrix<double, 1, 6> row;
  row << a(0) * b(0), a(0) * b(1) + a(1) * b(0), a(0) * b(2) + a(2) * b(0),
      a(1) * b(1), a(1) * b(2) + a(2) * b(1), a(2) * b(2);
  return row;
}

}  // namespace

ThinSvd StartSvd(const Eigen::MatrixXd& w, int num_bases) {
  const int count = static_cast<int>(std::min<Eigen::Index>(
      3 * static_cast<Eigen::Index>(num_bases), std::min(w.rows(), w.cols())));
  return ComputeTopSvd(w, count, SingularVectors::kBoth);
}

Status CheckRotationObservable(const Eigen::VectorXd& singular_values) {
  if (singular_values.size() < 3 ||
      !(singular_values(2) >=
        kMinThirdSingularValueRatio * singular_values(0)) ||
      !(singular_values(0) > 0.0)) {
    std::ostringstream msg;
    msg << "the centred 2D tracks have rank < 3 (sigma_3 / sigma_1 = "
        << (singular_values.size() >= 3 && singular_values(0) > 0.0
                ? singular_values(2) / singular_values(0)
                : 0.0)
        << " < " << kMinThirdSingularValueRatio
        << "): the sequence shows no rotation (or the object is flat), so "
           "depth is unobservable";
    return Status::Error(msg.str());
  }
  return Status::OK();
}

Status SolveMetricUpgrade(const Eigen::MatrixX3d& blocks,
                          MetricUpgrade* upgrade) {
  CHECK(upgrade != nullptr);
  CHECK_EQ(blocks.rows() % 2, 0);
  const int n = static_cast<int>(blocks.rows() / 2);
  if (n < 3) {
    return Status::Error("metric upgrade: needs at least 3 frames, got " +
                         std::to_string(n));
  }
  Eigen::MatrixXd equations(2 * n, 6);
  Eigen::Matrix<double, 1, 6> normalisation =
      Eigen::Matrix<double, 1, 6>::Zero();
  int used = 0;
  for (int i = 0; i < n; ++i) {
    Eigen::Matrix<double, 2, 3> m = blocks.middleRows<2>(2 * i);
    const double norm = m.norm();
    if (!(norm > 0.0)) {
      equations.middleRows<2>(2 * i).setZero();
      continue;
    }
    m /= norm;
    equations.row(2 * i) =
        BilinearRow(m.row(0), m.row(0)) - BilinearRow(m.row(1), m.row(1));
    equations.row(2 * i + 1) = BilinearRow(m.row(0), m.row(1));
    normalisation += 0.5 * (BilinearRow(m.row(0), m.row(0)) +
                            BilinearRow(m.row(1), m.row(1)));
    ++used;
  }
  if (used < 3) {
    return Status::Error(
        "metric upgrade: fewer than 3 frames have a non-zero motion block");
  }
  normalisation /= static_cast<double>(used);

  const ThinSvd svd = ComputeJacobiSvd(equations, SingularVectors::kRight);
  const Eigen::VectorXd& sigma = svd.singular_values;
  upgrade->conditioning = sigma(0) > 0.0 ? sigma(4) / sigma(0) : 0.0;
  if (!(upgrade->conditioning >= kMinMetricConditioning)) {
    std::ostringstream msg;
    msg << "metric upgrade: the orthonormality equations do not determine the "
           "metric (conditioning "
        << upgrade->conditioning << " < " << kMinMetricConditioning
        << "): the sequence shows no or too little rotation, so depth is "
           "unobservable";
    return Status::Error(msg.str());
  }
  Eigen::Matrix<double, 6, 1> h = svd.v.col(5);
  const double scale = normalisation.dot(h);
  if (!(std::abs(scale) > 1e-12)) {
    return Status::Error(
        "metric upgrade: the least-squares metric is degenerate (zero mean "
        "row norm)");
  }
  h /= scale;
  Eigen::Matrix3d hm;
  hm << h(0), h(1), h(2), h(1), h(3), h(4), h(2), h(4), h(5);

  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(hm);
  Eigen::Vector3d values = eig.eigenvalues();
  const double largest = values.maxCoeff();
  if (!(largest > 0.0)) {
    return Status::Error(
        "metric upgrade: the least-squares metric has no positive eigenvalue");
  }
  const double floor = kMinEigenvalueFraction * largest;
  upgrade->was_indefinite = values.minCoeff() < floor;
  values = values.cwiseMax(floor);
  const Eigen::Matrix3d& v = eig.eigenvectors();
  upgrade->h = v * values.asDiagonal() * v.transpose();
  upgrade->g = v * values.cwiseSqrt().asDiagonal() * v.transpose();
  VLOG(1) << "metric upgrade: " << used << " frames, conditioning "
          << upgrade->conditioning << ", eigenvalues of H "
          << eig.eigenvalues().transpose()
          << (upgrade->was_indefinite ? " (clamped)" : "");
  return Status::OK();
}

}  // namespace nrsfm
