#include "solvers/basis_weight_fit.h"

#include <cmath>
#include <vector>

#include <Eigen/Cholesky>
#include <glog/logging.h>

namespace nrsfm {
namespace {

Eigen::VectorXd SolveDamped(Eigen::MatrixXd normal, const Eigen::VectorXd& rhs,
                            double damping) {
  const double trace = normal.trace();
  const double n = static_cast<double>(normal.rows());
  normal.diagonal().array() += damping * (trace > 0.0 ? trace / n : 1.0) + 1e-300;
  return normal.ldlt().solve(rhs);
}

void CheckMonocular(const Measurements& centered, const Model& model) {
  CHECK_EQ(centered.num_cameras, 1);
  CHECK_EQ(model.num_cameras, 1);
  CHECK_EQ(centered.num_frames, model.num_frames);
  CHECK_EQ(centered.num_points, model.num_points);
}

}  // namespace

void FitBasisGivenMotion(const Measurements& centered, double damping,
                         Model* model) {
  CHECK(model != nullptr);
  CheckMonocular(centered, *model);
  const int k = model->num_bases;
  const int f = model->num_frames;
  // Q_t = [l_t1 Π R_t, …, l_tK Π R_t], 2 × 3K per frame.
  std::vector<Eigen::MatrixXd> q(f);
  for (int t = 0; t < f; ++t) {
    const Eigen::Matrix<double, 2, 3> pr = model->Rotation(t, 0).topRows<2>();
    q[t].resize(2, 3 * k);
    for (int b = 0; b < k; ++b) {
      q[t].middleCols(3 * b, 3) = model->weights(b, t) * pr;
    }
  }
  for (int p = 0; p < model->num_points; ++p) {
    Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(3 * k, 3 * k);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(3 * k);
    for (int t = 0; t < f; ++t) {
      if (!centered.visible(t, p)) continue;
      normal.noalias() += q[t].transpose() * q[t];
      rhs.noalias() += q[t].transpose() *
                       (centered.Observation(t, 0, p) - model->translations.col(t));
    }
    model->basis.col(p) = SolveDamped(normal, rhs, damping);
  }
}

void FitWeightsGivenBasis(const Measurements& centered, double damping,
                          bool fit_translations, Model* model) {
  CHECK(model != nullptr);
  CheckMonocular(centered, *model);
  const int k = model->num_bases;
  const int n = k + (fit_translations ? 2 : 0);
  for (int t = 0; t < model->num_frames; ++t) {
    const Eigen::Matrix<double, 2, 3> pr = model->Rotation(t, 0).topRows<2>();
    const Eigen::Vector2d fixed_shift =
        fit_translations ? Eigen::Vector2d::Zero()
                         : Eigen::Vector2d(model->translations.col(t));
    Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
    Eigen::MatrixXd design = Eigen::MatrixXd::Zero(2, n);
    if (fit_translations) design.rightCols<2>().setIdentity();
    for (int p = 0; p < model->num_points; ++p) {
      if (!centered.visible(t, p)) continue;
      // Columns: Π R_t S_b[:, p] for each b, then (with translations) I_2.
      for (int b = 0; b < k; ++b) {
        design.col(b) = pr * model->basis.block<3, 1>(3 * b, p);
      }
      normal.noalias() += design.transpose() * design;
      rhs.noalias() +=
          design.transpose() * (centered.Observation(t, 0, p) - fixed_shift);
    }
    const Eigen::VectorXd x = SolveDamped(normal, rhs, damping);
    model->weights.col(t) = x.head(k);
    if (fit_translations) model->translations.col(t) = x.tail<2>();
  }
}

void CentreBasisKeepingProjections(Model* model) {
  CHECK(model != nullptr);
  CHECK_EQ(model->num_cameras, 1);
  const int k = model->num_bases;
  Eigen::MatrixXd means(3, k);
  for (int b = 0; b < k; ++b) {
    means.col(b) = model->basis.middleRows(3 * b, 3).rowwise().mean();
    model->basis.middleRows(3 * b, 3).colwise() -= means.col(b);
  }
  for (int t = 0; t < model->num_frames; ++t) {
    model->translations.col(t) +=
        model->Rotation(t, 0).topRows<2>() * (means * model->weights.col(t));
  }
}

double CenteredCost(const Measurements& centered, const Model& model) {
  CheckMonocular(centered, model);
  double cost = 0.0;
  for (int t = 0; t < model.num_frames; ++t) {
    const Eigen::Matrix2Xd projected = model.Project(t, 0);
    for (int p = 0; p < model.num_points; ++p) {
      if (!centered.visible(t, p)) continue;
      cost += (centered.Observation(t, 0, p) - projected.col(p)).squaredNorm();
    }
  }
  return cost;
}

double CenteredRms(const Measurements& centered, const Model& model) {
  const int n = centered.NumVisible();
  return n > 0 ? std::sqrt(CenteredCost(centered, model) / n) : 0.0;
}

}  // namespace nrsfm
