#include "solvers/basis_weight_fit.h"

#include <glog/logging.h>

#include <Eigen/Cholesky>
#include <vector>

#include "core/parallel_for.h"

namespace nrsfm {
namespace {

Eigen::VectorXd SolveDamped(Eigen::MatrixXd normal, const Eigen::VectorXd& rhs,
                            double damping) {
  const double trace = normal.trace();
  const double n = static_cast<double>(normal.rows());
  normal.diagonal().array() +=
      damping * (trace > 0.0 ? trace / n : 1.0) + 1e-300;
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
                         Model* model, int num_threads) {
  CHECK(model != nullptr);
  CheckMonocular(centered, *model);
  const int k = model->num_bases;
  const int f = model->num_frames;
  const int num_points = model->num_points;
  // Q_t = [l_t1 Π R_t, …, l_tK Π R_t] = l_tᵀ ⊗ Π R_t (2 × 3K); stacked, Q is
  // 2F × 3K. Point p's normal matrix is Σ over the frames that see it of
  // Q_tᵀ Q_t = (l_t l_tᵀ) ⊗ (Π R_t)ᵀ Π R_t: the sum over all frames once,
  // minus the frames that do not see p (one rank update of their rows).
  Eigen::MatrixXd q(2 * f, 3 * k);
  for (int t = 0; t < f; ++t) {
    const Eigen::Matrix<double, 2, 3> pr = model->Rotation(t, 0).topRows<2>();
    for (int b = 0; b < k; ++b) {
      q.block<2, 3>(2 * t, 3 * b) = model->weights(b, t) * pr;
    }
  }
  Eigen::MatrixXd all_frames = Eigen::MatrixXd::Zero(3 * k, 3 * k);
  all_frames.selfadjointView<Eigen::Lower>().rankUpdate(q.transpose());
  all_frames.triangularView<Eigen::StrictlyUpper>() = all_frames.transpose();
  // Right-hand sides of every point at once: Qᵀ (w̃ − δT) over visible entries
  // (W and `visible` read column by column).
  Eigen::MatrixXd observed(2 * f, num_points);
  for (int p = 0; p < num_points; ++p) {
    for (int t = 0; t < f; ++t) {
      observed.block<2, 1>(2 * t, p) =
          centered.visible(t, p)
              ? Eigen::Vector2d(centered.Observation(t, 0, p) -
                                model->translations.col(t))
              : Eigen::Vector2d::Zero();
    }
  }
  const Eigen::MatrixXd rhs = q.transpose() * observed;
  ParallelFor(num_points, num_threads, /*grain=*/64, [&](int begin, int end) {
    Eigen::MatrixXd missing(2 * f, 3 * k);
    for (int p = begin; p < end; ++p) {
      Eigen::MatrixXd normal = all_frames;
      int rows = 0;
      for (int t = 0; t < f; ++t) {
        if (centered.visible(t, p)) continue;
        missing.middleRows<2>(rows) = q.middleRows<2>(2 * t);
        rows += 2;
      }
      if (rows > 0) {
        normal.selfadjointView<Eigen::Lower>().rankUpdate(
            missing.topRows(rows).transpose(), -1.0);
        normal.triangularView<Eigen::StrictlyUpper>() = normal.transpose();
      }
      model->basis.col(p) = SolveDamped(std::move(normal), rhs.col(p), damping);
    }
  });
}

void FitWeightsGivenBasis(const Measurements& centered, double damping,
                          bool fit_translations, Model* model,
                          int num_threads) {
  CHECK(model != nullptr);
  CheckMonocular(centered, *model);
  const int k = model->num_bases;
  const int num_points = model->num_points;
  const int n = k + (fit_translations ? 2 : 0);
  // Per frame the design matrix A (2P × n): rows 2p, 2p + 1 of point p hold
  // Π R_t S_b[:, p] in column b and, with translations, I_2; zero rows for
  // points the frame does not see.
  ParallelFor(
      model->num_frames, num_threads, /*grain=*/4, [&](int begin, int end) {
        Eigen::MatrixXd design(2 * num_points, n);
        Eigen::VectorXd observed(2 * num_points);
        for (int t = begin; t < end; ++t) {
          const Eigen::Matrix<double, 2, 3> pr =
              model->Rotation(t, 0).topRows<2>();
          const Eigen::Vector2d fixed_shift =
              fit_translations ? Eigen::Vector2d::Zero()
                               : Eigen::Vector2d(model->translations.col(t));
          for (int p = 0; p < num_points; ++p) {
            if (!centered.visible(t, p)) {
              design.middleRows<2>(2 * p).setZero();
              observed.segment<2>(2 * p).setZero();
              continue;
            }
            for (int b = 0; b < k; ++b) {
              design.block<2, 1>(2 * p, b) =
                  pr * model->basis.block<3, 1>(3 * b, p);
            }
            if (fit_translations) design.block<2, 2>(2 * p, k).setIdentity();
            observed.segment<2>(2 * p) =
                centered.Observation(t, 0, p) - fixed_shift;
          }
          Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(n, n);
          normal.selfadjointView<Eigen::Lower>().rankUpdate(design.transpose());
          normal.triangularView<Eigen::StrictlyUpper>() = normal.transpose();
          const Eigen::VectorXd x = SolveDamped(
              std::move(normal), design.transpose() * observed, damping);
          model->weights.col(t) = x.head(k);
          if (fit_translations) model->translations.col(t) = x.tail<2>();
        }
      });
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

}  // namespace nrsfm
