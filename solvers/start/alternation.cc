#include "solvers/start/alternation.h"

#include <glog/logging.h>

#include <cmath>
#include <string>

#include "core/eval/metrics.h"
#include "core/math/parallel_for.h"
#include "core/math/random.h"
#include "core/math/rotation.h"
#include "core/model/option_checker.h"
#include "solvers/start/basis_weight_fit.h"
#include "solvers/start/pose_fit.h"

namespace nrsfm {
namespace {

constexpr double kDamping = 1e-12;         // of the linear solves
constexpr int kRotationStepsPerRound = 3;  // Gauss-Newton steps per frame
constexpr double kStopRelativeDecrease = 1e-10;

// What a frame's pose cost Σ_p ||o_p − Π R X_p||² over its visible points
// needs of them: C = Σ X Xᵀ, D = Σ o Xᵀ and e = Σ ||o||².
struct PoseMoments {
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  Eigen::Matrix<double, 2, 3> d = Eigen::Matrix<double, 2, 3>::Zero();
  double e = 0.0;

  double Cost(const Eigen::Matrix3d& rotation) const {
    const Eigen::Matrix<double, 2, 3> pr = rotation.topRows<2>();
    return e - 2.0 * (pr.cwiseProduct(d)).sum() +
           (pr * c).cwiseProduct(pr).sum();
  }
};

// Up to `max_steps` Gauss-Newton steps on the rotation, each kept only if
// it lowers the cost: RefineRotation's steps (solvers/start/pose_fit.h, scale
// 1), with its sums over points formed from the moments, so that a step costs
// O(1) instead of O(P). With x = R X, M = Σ x xᵀ = R C Rᵀ and N = Σ o xᵀ =
// D Rᵀ: JᵀJ = [[M_zz, 0, −M_xz], [0, M_zz, −M_yz], [−M_xz, −M_yz, M_xx +
// M_yy]] and Jᵀe = (M_yz − N_yz, N_xz − M_xz, N_yx − N_xy).
void RefineRotationFromMoments(const PoseMoments& moments, int max_steps,
                               Eigen::Matrix3d* rotation) {
  double cost = moments.Cost(*rotation);
  for (int step = 0; step < max_steps; ++step) {
    const Eigen::Matrix3d m = *rotation * moments.c * rotation->transpose();
    const Eigen::Matrix<double, 2, 3> n = moments.d * rotation->transpose();
    Eigen::Matrix3d jtj;
    jtj << m(2, 2), 0.0, -m(0, 2), 0.0, m(2, 2), -m(1, 2), -m(0, 2), -m(1, 2),
        m(0, 0) + m(1, 1);
    const Eigen::Vector3d jte(m(1, 2) - n(1, 2), n(0, 2) - m(0, 2),
                              n(1, 0) - n(0, 1));
    jtj.diagonal().array() += 1e-12 * jtj.trace() + 1e-300;
    const Eigen::Vector3d omega = jtj.ldlt().solve(jte);
    if (!omega.allFinite()) break;
    const Eigen::Matrix3d candidate = AngleAxisToRotation(omega) * (*rotation);
    const double candidate_cost = moments.Cost(candidate);
    if (!(candidate_cost < cost)) break;
    *rotation = candidate;
    cost = candidate_cost;
  }
}

// One rotation update per frame (step 2 of the header), over visible points.
// Frames run on up to `num_threads` threads, each on its own.
void RefineRotations(const FrameMajorTracks& tracks, int num_threads,
                     Model* model) {
  const int k = model->num_bases;
  ParallelFor(
      model->num_frames, num_threads, /*grain=*/4, [&](int begin, int end) {
        for (int t = begin; t < end; ++t) {
          PoseMoments moments;
          const Eigen::Vector2d shift = model->translations.col(t);
          for (int p = 0; p < model->num_points; ++p) {
            if (!tracks.seen(p, t)) continue;
            // The point of frame t's shape, summed as ShapeInObject does.
            Eigen::Vector3d x = Eigen::Vector3d::Zero();
            for (int b = 0; b < k; ++b) {
              x += model->weights(b, t) * model->basis.block<3, 1>(3 * b, p);
            }
            const Eigen::Vector2d o = tracks.w.block<2, 1>(2 * p, t) - shift;
            moments.c.noalias() += x * x.transpose();
            moments.d.noalias() += o * x.transpose();
            moments.e += o.squaredNorm();
          }
          Eigen::Matrix3d rotation = model->Rotation(t, 0);
          RefineRotationFromMoments(moments, kRotationStepsPerRound, &rotation);
          model->SetRotation(t, 0, rotation);
        }
      });
}

// Rescales bases k ≥ 1 (0-based) to the norm of basis 0; weights inversely.
void BalanceBases(Model* model) {
  const double reference = model->basis.topRows(3).norm();
  for (int k = 1; k < model->num_bases; ++k) {
    const double norm = model->basis.middleRows(3 * k, 3).norm();
    if (!(norm > 0.0) || !(reference > 0.0)) continue;
    const double factor = reference / norm;
    model->basis.middleRows(3 * k, 3) *= factor;
    model->weights.row(k) /= factor;
  }
}

}  // namespace

Status AlternationOptions::Check() const {
  OptionChecker check("alternation options");
  check.AtLeast("rounds", rounds, 0);
  check.FiniteAtLeast("initial_deformation", initial_deformation, 0.0);
  return check.status();
}

Status CheckAlternationInput(const Measurements& centered, int num_bases,
                             const AlternationOptions& options) {
  CHECK_EQ(centered.num_cameras, 1);
  NRSFM_RETURN_IF_ERROR(options.Check());
  const int f = centered.num_frames;
  const int p = centered.num_points;
  if (num_bases < 1 || 2 * f < 3 || p < 4) {
    return Status::Error("needs K >= 1, 2F >= 3 and P >= 4; got K = " +
                         std::to_string(num_bases) + ", F = " +
                         std::to_string(f) + ", P = " + std::to_string(p));
  }
  return Status::OK();
}

void AlternateFromRigid(const Measurements& centered, int num_bases,
                        const std::vector<Eigen::Matrix3d>& rotations,
                        const Eigen::VectorXd& scales,
                        const Eigen::Matrix3Xd& rigid_shape,
                        const AlternationOptions& options, std::uint64_t seed,
                        bool update_rotations, Model* model,
                        AlternationSummary* summary, int num_threads) {
  CHECK(model != nullptr && summary != nullptr);
  CHECK_EQ(centered.num_cameras, 1);
  const Status valid = options.Check();
  CHECK(valid.ok()) << valid.message();
  const int f = centered.num_frames;
  const int k = num_bases;
  CHECK_GE(k, 1);
  CHECK_EQ(static_cast<int>(rotations.size()), f);
  CHECK_EQ(scales.size(), f);
  CHECK_EQ(rigid_shape.cols(), centered.num_points);
  *summary = AlternationSummary();

  // Step 1: the rigid model plus small random weights for the other bases.
  model->Resize(f, 1, centered.num_points, k);
  Random random(seed);
  for (int t = 0; t < f; ++t) {
    model->SetRotation(t, 0, rotations[t]);
    model->weights(0, t) = scales[t];
    for (int b = 1; b < k; ++b) {
      model->weights(b, t) =
          options.initial_deformation * random.NormalUnpaired();
    }
  }
  model->SetBasisShape(0, rigid_shape);
  double cost = ReprojectionSquaredError(centered, *model, num_threads);
  summary->rigid_rms = std::sqrt(cost / centered.NumVisible());

  // Step 2: the alternation.
  const FrameMajorTracks tracks(centered, num_threads);
  int rounds = 0;
  for (int round = 0; round < options.rounds; ++round) {
    FitBasisGivenMotion(centered, kDamping, model, num_threads);
    CentreBasisKeepingProjections(model);
    FitWeightsGivenBasis(tracks, kDamping, /*fit_translations=*/true, model,
                         num_threads);
    BalanceBases(model);
    if (update_rotations) RefineRotations(tracks, num_threads, model);
    ++rounds;
    const double previous = cost;
    cost = ReprojectionSquaredError(centered, *model, num_threads);
    VLOG(2) << "alternation round " << round + 1 << ": RMS "
            << std::sqrt(cost / centered.NumVisible());
    if (!(previous - cost > kStopRelativeDecrease * previous)) break;
  }
  VLOG(1) << "alternation: K = " << k << ", rigid RMS " << summary->rigid_rms
          << ", after " << rounds << " rounds "
          << std::sqrt(cost / centered.NumVisible());
}

}  // namespace nrsfm
