#include "solvers/alternation.h"

#include <glog/logging.h>

#include <cmath>
#include <string>

#include "core/metrics.h"
#include "core/option_checker.h"
#include "core/random.h"
#include "solvers/basis_weight_fit.h"
#include "solvers/pose_fit.h"

namespace nrsfm {
namespace {

constexpr double kDamping = 1e-12;         // of the linear solves
constexpr int kRotationStepsPerRound = 3;  // Gauss-Newton steps per frame
constexpr double kStopRelativeDecrease = 1e-10;

// One rotation update per frame (step 2 of the header), over visible points.
void RefineRotations(const Measurements& centered, Model* model) {
  for (int t = 0; t < model->num_frames; ++t) {
    const Eigen::Matrix3Xd shape = model->ShapeInObject(t);
    const int n = static_cast<int>(centered.visible.row(t).count());
    Eigen::Matrix2Xd observed(2, n);
    Eigen::Matrix3Xd points(3, n);
    for (int p = 0, j = 0; p < model->num_points; ++p) {
      if (!centered.visible(t, p)) continue;
      observed.col(j) =
          centered.Observation(t, 0, p) - model->translations.col(t);
      points.col(j) = shape.col(p);
      ++j;
    }
    Eigen::Matrix3d rotation = model->Rotation(t, 0);
    RefineRotation(observed, points, 1.0, kRotationStepsPerRound, &rotation);
    model->SetRotation(t, 0, rotation);
  }
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
                        AlternationSummary* summary) {
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
  double cost = ReprojectionSquaredError(centered, *model);
  summary->rigid_rms = std::sqrt(cost / centered.NumVisible());

  // Step 2: the alternation.
  int rounds = 0;
  for (int round = 0; round < options.rounds; ++round) {
    FitBasisGivenMotion(centered, kDamping, model);
    CentreBasisKeepingProjections(model);
    FitWeightsGivenBasis(centered, kDamping, /*fit_translations=*/true, model);
    BalanceBases(model);
    if (update_rotations) RefineRotations(centered, model);
    ++rounds;
    const double previous = cost;
    cost = ReprojectionSquaredError(centered, *model);
    VLOG(2) << "alternation round " << round + 1 << ": RMS "
            << std::sqrt(cost / centered.NumVisible());
    if (!(previous - cost > kStopRelativeDecrease * previous)) break;
  }
  VLOG(1) << "alternation: K = " << k << ", rigid RMS " << summary->rigid_rms
          << ", after " << rounds << " rounds "
          << std::sqrt(cost / centered.NumVisible());
}

}  // namespace nrsfm
