#include "solvers/start/pose_fit.h"

#include <glog/logging.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>

#include "core/math/rotation.h"

namespace nrsfm {

void ScaledRotationFromTwoRows(const Eigen::Matrix<double, 2, 3>& m,
                               Eigen::Matrix3d* rotation, double* scale) {
  CHECK(rotation != nullptr && scale != nullptr);
  if (!(m.squaredNorm() > 0.0)) {
    rotation->setIdentity();
    *scale = 0.0;
    return;
  }
  const Eigen::JacobiSVD<Eigen::Matrix<double, 2, 3>> svd(
      m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix<double, 2, 3> rows =
      svd.matrixU() * svd.matrixV().leftCols<2>().transpose();
  rotation->topRows<2>() = rows;
  rotation->row(2) = rows.row(0).cross(rows.row(1));
  *scale = 0.5 * (svd.singularValues()(0) + svd.singularValues()(1));
}

double PoseCost(const Eigen::Matrix2Xd& observed,
                const Eigen::Matrix3Xd& points, double scale,
                const Eigen::Matrix3d& rotation) {
  CHECK_EQ(observed.cols(), points.cols());
  return (observed - scale * (rotation.topRows<2>() * points)).squaredNorm();
}

double RefineRotation(const Eigen::Matrix2Xd& observed,
                      const Eigen::Matrix3Xd& points, double scale,
                      int max_steps, Eigen::Matrix3d* rotation) {
  CHECK(rotation != nullptr);
  double cost = PoseCost(observed, points, scale, *rotation);
  for (int step = 0; step < max_steps; ++step) {
    const Eigen::Matrix3Xd x = scale * (*rotation) * points;
    // d(Π [ω]× x)/dω = −Π [x]× = [[0, z, −y], [−z, 0, x]].
    Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
    Eigen::Vector3d jte = Eigen::Vector3d::Zero();
    for (Eigen::Index p = 0; p < x.cols(); ++p) {
      Eigen::Matrix<double, 2, 3> j;
      j << 0.0, x(2, p), -x(1, p), -x(2, p), 0.0, x(0, p);
      const Eigen::Vector2d e = observed.col(p) - x.col(p).head<2>();
      jtj += j.transpose() * j;
      jte += j.transpose() * e;
    }
    jtj.diagonal().array() += 1e-12 * jtj.trace() + 1e-300;
    const Eigen::Vector3d omega = jtj.ldlt().solve(jte);
    if (!omega.allFinite()) break;
    const Eigen::Matrix3d candidate = AngleAxisToRotation(omega) * (*rotation);
    const double candidate_cost = PoseCost(observed, points, scale, candidate);
    if (!(candidate_cost < cost)) break;
    *rotation = candidate;
    cost = candidate_cost;
  }
  return cost;
}

bool FitWeakPerspectivePose(const Eigen::Matrix2Xd& observed,
                            const Eigen::Matrix3Xd& points, int max_steps,
                            Eigen::Matrix3d* rotation, double* scale) {
  CHECK(rotation != nullptr && scale != nullptr);
  CHECK_EQ(observed.cols(), points.cols());
  if (points.cols() < 4) return false;
  const Eigen::Matrix3d xxt = points * points.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(xxt);
  if (!(eig.eigenvalues()(0) > 1e-12 * eig.eigenvalues()(2))) return false;
  const Eigen::Matrix<double, 2, 3> affine =
      (observed * points.transpose()) * xxt.inverse();
  Eigen::Matrix3d r;
  double s = 0.0;
  ScaledRotationFromTwoRows(affine, &r, &s);
  if (!(s > 0.0)) return false;
  for (int round = 0; round < max_steps; ++round) {
    const double before = PoseCost(observed, points, s, r);
    RefineRotation(observed, points, s, 1, &r);
    const Eigen::Matrix2Xd projected = r.topRows<2>() * points;
    const double denominator = projected.squaredNorm();
    if (!(denominator > 0.0)) return false;
    const double new_scale =
        (observed.array() * projected.array()).sum() / denominator;
    if (new_scale > 0.0) s = new_scale;
    if (!(PoseCost(observed, points, s, r) < before)) break;
  }
  if (!(s > 0.0) || !r.allFinite()) return false;
  *rotation = r;
  *scale = s;
  return true;
}

}  // namespace nrsfm
