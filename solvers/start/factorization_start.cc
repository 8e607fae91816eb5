#include "solvers/start/factorization_start.h"

#include <glog/logging.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <sstream>
#include <vector>

#include "core/math/svd.h"
#include "solvers/start/metric_upgrade.h"
#include "solvers/start/pose_fit.h"

namespace nrsfm {

Status FactorizationStart(const Measurements& centered, int num_bases,
                          Model* model, FactorizationStartSummary* summary,
                          const ThinSvd* given_svd) {
  CHECK(model != nullptr && summary != nullptr);
  CHECK_EQ(centered.num_cameras, 1);
  const int f = centered.num_frames;
  const int p = centered.num_points;
  const int k = num_bases;
  const int r = 3 * k;
  if (k < 1 || r > 2 * f || r + 1 > p) {
    std::ostringstream msg;
    msg << "factorisation start: K = " << k
        << " needs K >= 1, 3K <= 2F and 3K + 1 <= P; got F = " << f
        << ", P = " << p;
    return Status::Error(msg.str());
  }
  *summary = FactorizationStartSummary();

  ThinSvd computed;
  if (given_svd == nullptr) {
    computed = StartSvd(centered.W, k);
  }
  const ThinSvd& svd = given_svd != nullptr ? *given_svd : computed;
  CHECK_GE(svd.u.cols(), r);
  CHECK_GE(svd.v.cols(), r);
  NRSFM_RETURN_IF_ERROR(CheckRotationObservable(svd.singular_values)
                            .WithContext("factorisation start"));
  const Eigen::VectorXd root = svd.singular_values.head(r).cwiseSqrt();
  const Eigen::MatrixXd q_hat = svd.u.leftCols(r) * root.asDiagonal();
  const Eigen::MatrixXd b_hat =
      root.asDiagonal() * svd.v.leftCols(r).transpose();

  // Step 2: rank-1 factorisation of every reordered block.
  Eigen::MatrixXd l_hat(k, f);
  Eigen::MatrixX3d blocks(2 * f, 3);
  double defect_sum = 0.0;
  for (int t = 0; t < f; ++t) {
    Eigen::MatrixXd reordered(k, 6);
    for (int b = 0; b < k; ++b) {
      reordered.block<1, 3>(b, 0) = q_hat.block<1, 3>(2 * t, 3 * b);
      reordered.block<1, 3>(b, 3) = q_hat.block<1, 3>(2 * t + 1, 3 * b);
    }
    const ThinSvd block_svd =
        ComputeJacobiSvd(reordered, SingularVectors::kBoth);
    const Eigen::VectorXd& s = block_svd.singular_values;
    l_hat.col(t) = s(0) * block_svd.u.col(0);
    const Eigen::VectorXd v = block_svd.v.col(0);
    blocks.row(2 * t) = v.head<3>().transpose();
    blocks.row(2 * t + 1) = v.tail<3>().transpose();
    if (s.size() > 1 && s(0) > 0.0) defect_sum += s(1) / s(0);
  }
  summary->mean_subblock_rank1_defect = defect_sum / f;

  // Consistent signs: l̂_t · d ≥ 0 for the principal direction d of all l̂_t.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> principal(
      l_hat * l_hat.transpose());
  const Eigen::VectorXd direction = principal.eigenvectors().col(k - 1);
  for (int t = 0; t < f; ++t) {
    if (l_hat.col(t).dot(direction) < 0.0) {
      l_hat.col(t) *= -1.0;
      blocks.middleRows<2>(2 * t) *= -1.0;
    }
  }

  // Step 3: metric upgrade.
  MetricUpgrade upgrade;
  NRSFM_RETURN_IF_ERROR(
      SolveMetricUpgrade(blocks, &upgrade).WithContext("factorisation start"));
  summary->metric_upgrade_was_indefinite = upgrade.was_indefinite;

  model->Resize(f, 1, p, k);
  for (int t = 0; t < f; ++t) {
    const Eigen::Matrix<double, 2, 3> m =
        blocks.middleRows<2>(2 * t) * upgrade.g;
    Eigen::Matrix3d rotation;
    double scale = 0.0;
    ScaledRotationFromTwoRows(m, &rotation, &scale);
    model->SetRotation(t, 0, rotation);
    model->weights.col(t) = scale * l_hat.col(t);
  }
  const Eigen::Matrix3d g_inverse = upgrade.g.inverse();
  for (int b = 0; b < k; ++b) {
    model->SetBasisShape(b, g_inverse * b_hat.middleRows(3 * b, 3));
  }
  VLOG(1) << "factorisation start: K = " << k
          << ", mean sub-block rank-1 defect "
          << summary->mean_subblock_rank1_defect;
  return Status::OK();
}

}  // namespace nrsfm
