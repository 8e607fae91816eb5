#include "solvers/start/basis_weight_fit.h"

#include <glog/logging.h>

#include <Eigen/Cholesky>
#include <vector>

#include "core/math/parallel_for.h"

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

FrameMajorTracks::FrameMajorTracks(const Measurements& centered,
                                   int num_threads)
    : w(2 * centered.num_points, centered.num_frames),
      seen(centered.num_points, centered.num_frames) {
  CHECK_EQ(centered.num_cameras, 1);
  const int f = centered.num_frames;
  ParallelFor(centered.num_points, num_threads, 256, [&](int begin, int end) {
    for (int p = begin; p < end; ++p) {
      for (int t = 0; t < f; ++t) {
        w(2 * p, t) = centered.W(2 * t, p);
        w(2 * p + 1, t) = centered.W(2 * t + 1, p);
        seen(p, t) = centered.visible(t, p);
      }
    }
  });
}

void FitWeightsGivenBasis(const Measurements& centered, double damping,
                          bool fit_translations, Model* model,
                          int num_threads) {
  CHECK(model != nullptr);
  CheckMonocular(centered, *model);
  FitWeightsGivenBasis(FrameMajorTracks(centered, num_threads), damping,
                       fit_translations, model, num_threads);
}

void FitWeightsGivenBasis(const FrameMajorTracks& tracks, double damping,
                          bool fit_translations, Model* model,
                          int num_threads) {
  CHECK(model != nullptr);
  CHECK_EQ(model->num_cameras, 1);
  CHECK_EQ(tracks.seen.cols(), model->num_frames);
  CHECK_EQ(tracks.seen.rows(), model->num_points);
  const int k = model->num_bases;
  const int num_points = model->num_points;
  const int n = k + (fit_translations ? 2 : 0);
  using Basis = Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic>>;
  // Per frame the normal equations of the design A (2P × n): rows 2p,
  // 2p + 1 of point p hold Π R_t S_b[:, p] in column b and, with
  // translations, I_2; points the frame does not see have no rows. With
  // B_p = [S_1[:, p] … S_K[:, p]] (3 × K) and C = (Π R_t)ᵀ Π R_t, the
  // weights' block is Σ_p B_pᵀ C B_p = Σ_ij C_ij Σ_p B_p(i, :)ᵀ B_p(j, :):
  // the point sums over all points are formed once, and a frame subtracts
  // the points it does not see (or sums the ones it sees, when fewer).
  // moments[3 i + j] = Σ_p B_p(i, :)ᵀ B_p(j, :) (K × K), j ≤ i; column sums.
  std::vector<Eigen::MatrixXd> moments(9, Eigen::MatrixXd::Zero(k, k));
  Eigen::Matrix3Xd sums = Eigen::Matrix3Xd::Zero(3, k);
  for (int p = 0; p < num_points; ++p) {
    const Basis basis(model->basis.col(p).data(), 3, k);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j <= i; ++j) {
        moments[3 * i + j].noalias() += basis.row(i).transpose() * basis.row(j);
      }
    }
    sums += basis;
  }
  ParallelFor(
      model->num_frames, num_threads, /*grain=*/4, [&](int begin, int end) {
        Eigen::MatrixXd c_basis(3, k), block(k, k);
        for (int t = begin; t < end; ++t) {
          const Eigen::Matrix<double, 2, 3> pr =
              model->Rotation(t, 0).topRows<2>();
          const Eigen::Matrix3d c = pr.transpose() * pr;
          const Eigen::Vector2d fixed_shift =
              fit_translations ? Eigen::Vector2d::Zero()
                               : Eigen::Vector2d(model->translations.col(t));
          int seen = 0;
          for (int p = 0; p < num_points; ++p)
            seen += tracks.seen(p, t) ? 1 : 0;
          // Sum over the points seen (sign +1), or over all minus the
          // points not seen (sign −1), whichever is shorter.
          const bool subtract = 2 * seen > num_points;
          const double sign = subtract ? -1.0 : 1.0;
          Eigen::MatrixXd weights_block = Eigen::MatrixXd::Zero(k, k);
          Eigen::Matrix3Xd column_sums = Eigen::Matrix3Xd::Zero(3, k);
          if (subtract) {
            for (int i = 0; i < 3; ++i) {
              for (int j = 0; j <= i; ++j) {
                const double cij = c(i, j);
                if (i == j) {
                  weights_block += cij * moments[3 * i + j];
                } else {
                  weights_block += cij * (moments[3 * i + j] +
                                          moments[3 * i + j].transpose());
                }
              }
            }
            column_sums = sums;
          }
          Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
          Eigen::Vector2d observed_sum = Eigen::Vector2d::Zero();
          for (int p = 0; p < num_points; ++p) {
            const bool visible = tracks.seen(p, t);
            const Basis basis(model->basis.col(p).data(), 3, k);
            if (visible) {
              // Σ_p B_pᵀ (Π R_t)ᵀ w̃_tp.
              const Eigen::Vector2d observed =
                  tracks.w.block<2, 1>(2 * p, t) - fixed_shift;
              rhs.head(k).noalias() +=
                  basis.transpose() * (pr.transpose() * observed);
              observed_sum += observed;
            }
            if (visible != subtract) {
              c_basis.noalias() = c * basis;
              block.noalias() = basis.transpose() * c_basis;
              weights_block += sign * block;
              column_sums += sign * basis;
            }
          }
          if (fit_translations) rhs.tail<2>() = observed_sum;
          Eigen::MatrixXd normal(n, n);
          normal.topLeftCorner(k, k) = weights_block;
          if (fit_translations) {
            // Columns of T: Σ_p (Π R_t S_b[:, p])ᵀ I_2 = (Π R_t Σ_p B_p)ᵀ.
            const Eigen::MatrixXd cross = pr * column_sums;  // 2 × K
            normal.topRightCorner(k, 2) = cross.transpose();
            normal.bottomLeftCorner(2, k) = cross;
            normal.bottomRightCorner<2, 2>() =
                static_cast<double>(seen) * Eigen::Matrix2d::Identity();
          }
          const Eigen::VectorXd x =
              SolveDamped(std::move(normal), rhs, damping);
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
