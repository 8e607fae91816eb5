#include "solvers/start/rigid_start.h"

#include <glog/logging.h>

#include <Eigen/LU>
#include <vector>

#include "core/math/svd.h"
#include "solvers/start/metric_upgrade.h"
#include "solvers/start/pose_fit.h"

namespace nrsfm {

Status RigidStart(const Measurements& centered, int num_bases,
                  const AlternationOptions& options, std::uint64_t seed,
                  Model* model, RigidStartSummary* summary,
                  const ThinSvd* given_svd, int num_threads) {
  CHECK(model != nullptr && summary != nullptr);
  NRSFM_RETURN_IF_ERROR(CheckAlternationInput(centered, num_bases, options)
                            .WithContext("rigid start"));
  const int k = num_bases;
  *summary = RigidStartSummary();

  // Step 1: Tomasi-Kanade with the metric upgrade.
  ThinSvd computed;
  if (given_svd == nullptr) {
    computed = StartSvd(centered.W, k);
  }
  const ThinSvd& svd = given_svd != nullptr ? *given_svd : computed;
  CHECK_GE(svd.u.cols(), 3);
  CHECK_GE(svd.v.cols(), 3);
  NRSFM_RETURN_IF_ERROR(
      CheckRotationObservable(svd.singular_values).WithContext("rigid start"));
  const Eigen::Vector3d root = svd.singular_values.head<3>().cwiseSqrt();
  const Eigen::MatrixX3d q_hat = svd.u.leftCols<3>() * root.asDiagonal();
  const Eigen::Matrix3Xd b_hat =
      root.asDiagonal() * svd.v.leftCols<3>().transpose();
  MetricUpgrade upgrade;
  NRSFM_RETURN_IF_ERROR(
      SolveMetricUpgrade(q_hat, &upgrade).WithContext("rigid start"));
  summary->metric_upgrade_was_indefinite = upgrade.was_indefinite;
  const int f = centered.num_frames;
  std::vector<Eigen::Matrix3d> rotations(f);
  Eigen::VectorXd scales(f);
  for (int t = 0; t < f; ++t) {
    ScaledRotationFromTwoRows(q_hat.middleRows<2>(2 * t) * upgrade.g,
                              &rotations[t], &scales[t]);
  }
  const Eigen::Matrix3Xd rigid_shape = upgrade.g.inverse() * b_hat;

  // Step 2: the alternation, rotations included.
  AlternateFromRigid(centered, k, rotations, scales, rigid_shape, options, seed,
                     /*update_rotations=*/true, model, &summary->alternation,
                     num_threads);
  return Status::OK();
}

}  // namespace nrsfm
