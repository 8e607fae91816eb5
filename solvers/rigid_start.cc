#include "solvers/rigid_start.h"

#include <cmath>
#include <sstream>
#include <vector>

#include <Eigen/LU>
#include <glog/logging.h>

#include "core/random.h"
#include "core/svd.h"
#include "solvers/basis_weight_fit.h"
#include "solvers/metric_upgrade.h"
#include "solvers/pose_fit.h"

namespace nrsfm {
namespace {

constexpr double kDamping = 1e-12;            // of the linear solves
constexpr int kRotationStepsPerRound = 3;     // Gauss-Newton steps per frame
constexpr double kStopRelativeDecrease = 1e-10;

// One rotation update per frame (step 3 of the header), over visible points.
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

Status RigidStartOptions::Check() const {
  std::ostringstream msg;
  if (refine_iterations < 0) {
    msg << "rigid start: refine_iterations must be >= 0, got " << refine_iterations;
  } else if (!(initial_deformation >= 0.0) || !std::isfinite(initial_deformation)) {
    msg << "rigid start: initial_deformation must be finite and >= 0, got "
        << initial_deformation;
  } else {
    return Status::OK();
  }
  return Status::Error(msg.str());
}

Status RigidStart(const Measurements& centered, int num_bases,
                  const RigidStartOptions& options, Model* model,
                  RigidStartSummary* summary) {
  CHECK(model != nullptr && summary != nullptr);
  CHECK_EQ(centered.num_cameras, 1);
  NRSFM_RETURN_IF_ERROR(options.Check());
  const int f = centered.num_frames;
  const int p = centered.num_points;
  const int k = num_bases;
  if (k < 1 || 2 * f < 3 || p < 4) {
    std::ostringstream msg;
    msg << "rigid start: needs K >= 1, 2F >= 3 and P >= 4; got K = " << k
        << ", F = " << f << ", P = " << p;
    return Status::Error(msg.str());
  }
  *summary = RigidStartSummary();

  // Step 1: rotations, scales and rigid shape.
  std::vector<Eigen::Matrix3d> rotations;
  Eigen::VectorXd scales;
  Eigen::Matrix3Xd rigid_shape;
  if (options.rotations_from_triple) {
    NRSFM_RETURN_IF_ERROR(RotationsFromTriple(centered, k, options.triple,
                                              &rotations, &scales, &rigid_shape,
                                              &summary->triple)
                              .WithContext("rigid start"));
  } else {
    // Tomasi-Kanade with the metric upgrade.
    const ThinSvd svd = ComputeThinSvd(centered.W, SingularVectors::kBoth);
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
    summary->metric_upgrade_conditioning = upgrade.conditioning;
    rotations.resize(f);
    scales.resize(f);
    for (int t = 0; t < f; ++t) {
      ScaledRotationFromTwoRows(q_hat.middleRows<2>(2 * t) * upgrade.g,
                                &rotations[t], &scales[t]);
    }
    rigid_shape = upgrade.g.inverse() * b_hat;
  }

  // Step 2: the rigid model plus small random weights for the other bases.
  model->Resize(f, 1, p, k);
  Random normal(options.seed);
  for (int t = 0; t < f; ++t) {
    model->SetRotation(t, 0, rotations[t]);
    model->weights(0, t) = scales[t];
    for (int b = 1; b < k; ++b) {
      model->weights(b, t) = options.initial_deformation * normal.NormalUnpaired();
    }
  }
  model->SetBasisShape(0, rigid_shape);
  double cost = CenteredCost(centered, *model);
  summary->rigid_rms = std::sqrt(cost / centered.NumVisible());

  // Step 3: alternation.
  for (int round = 0; round < options.refine_iterations; ++round) {
    FitBasisGivenMotion(centered, kDamping, model);
    CentreBasisKeepingProjections(model);
    FitWeightsGivenBasis(centered, kDamping, /*fit_translations=*/true, model);
    BalanceBases(model);
    // The triple's rotations are exact on noise-free data; rotation updates
    // against a still-wrong basis would only move them away.
    if (!options.rotations_from_triple) RefineRotations(centered, model);
    ++summary->iterations;
    const double previous = cost;
    cost = CenteredCost(centered, *model);
    VLOG(2) << "rigid start round " << round + 1 << ": RMS "
            << std::sqrt(cost / centered.NumVisible());
    if (!(previous - cost > kStopRelativeDecrease * previous)) break;
  }
  summary->final_rms = std::sqrt(cost / centered.NumVisible());
  VLOG(1) << "rigid start: K = " << k << ", rigid RMS " << summary->rigid_rms
          << ", after " << summary->iterations << " rounds " << summary->final_rms;
  return Status::OK();
}

}  // namespace nrsfm
