#include "solvers/prior_rule.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/option_checker.h"
#include "core/rotation.h"

namespace nrsfm {
namespace {

constexpr double kDegreesPerRadian = 180.0 / M_PI;

double Median(std::vector<double> values) {
  if (values.empty()) return -1.0;
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + mid, values.end());
  return values[mid];
}

}  // namespace

Status PriorRuleOptions::Check() const {
  OptionChecker check("prior rule options");
  check.FinitePositive("max_track_step", max_track_step);
  check.FinitePositive("min_basis_fraction", min_basis_fraction);
  check.FinitePositive("temporal_shape_weight", temporal_shape_weight);
  check.FiniteAtLeast("max_path_acceleration_deg", max_path_acceleration_deg, 0.0);
  check.FinitePositive("rotation_acceleration_weight", rotation_acceleration_weight);
  return check.status();
}

double MedianTrackStep(const Measurements& measurements) {
  const double spread = measurements.ImageSpreadRms();
  if (!(spread > 0.0)) return -1.0;
  std::vector<double> steps;
  for (int t = 1; t < measurements.num_frames; ++t) {
    double sum = 0.0;
    int count = 0;
    for (int c = 0; c < measurements.num_cameras; ++c) {
      const int view = measurements.View(t, c);
      const int previous = measurements.View(t - 1, c);
      for (int p = 0; p < measurements.num_points; ++p) {
        if (!measurements.visible(view, p) || !measurements.visible(previous, p)) continue;
        sum += (measurements.W.block<2, 1>(2 * view, p) -
                measurements.W.block<2, 1>(2 * previous, p))
                   .squaredNorm();
        ++count;
      }
    }
    if (count > 0) steps.push_back(std::sqrt(sum / count) / spread);
  }
  return Median(std::move(steps));
}

double MedianPathAccelerationDeg(const Model& model) {
  if (model.num_frames < 3) return -1.0;
  std::vector<double> accelerations;
  accelerations.reserve(model.num_frames - 2);
  Eigen::Vector3d previous_step =
      RotationToAngleAxis(model.Rotation(1, 0) * model.Rotation(0, 0).transpose());
  for (int t = 1; t + 1 < model.num_frames; ++t) {
    const Eigen::Vector3d step =
        RotationToAngleAxis(model.Rotation(t + 1, 0) * model.Rotation(t, 0).transpose());
    accelerations.push_back((step - previous_step).norm() * kDegreesPerRadian);
    previous_step = step;
  }
  return Median(std::move(accelerations));
}

void DecideVideoPriors(const PriorRuleOptions& options,
                       const Measurements& measurements, int num_bases,
                       PriorDecision* decision) {
  decision->track_step = MedianTrackStep(measurements);
  decision->video =
      decision->track_step >= 0.0 && decision->track_step < options.max_track_step;
  decision->basis_absorbs_rotation =
      3.0 * num_bases >= options.min_basis_fraction * measurements.num_points;
  if (decision->video && decision->basis_absorbs_rotation) {
    decision->term_weights["temporal_shape"] = options.temporal_shape_weight;
  }
}

void DecidePathPrior(const PriorRuleOptions& options, const Model& start,
                     PriorDecision* decision) {
  if (decision->term_weights.count("temporal_shape") == 0) return;
  decision->path_acceleration_deg = MedianPathAccelerationDeg(start);
  decision->constant_angular_velocity =
      decision->path_acceleration_deg >= 0.0 &&
      decision->path_acceleration_deg < options.max_path_acceleration_deg;
  if (decision->constant_angular_velocity) {
    decision->term_weights["rotation_acceleration"] =
        options.rotation_acceleration_weight;
  }
}

double LargestViewAngleDeg(const Model& model) {
  // The angle of R_t R_sᵀ from its trace, 1 + 2 cos θ = Σ_ij (R_t)_ij (R_s)_ij:
  // ample precision for the tens of degrees this is about, O(F²) cheap.
  std::vector<Eigen::Matrix3d> rotations(model.num_frames);
  for (int t = 0; t < model.num_frames; ++t) rotations[t] = model.Rotation(t, 0);
  double smallest_cosine = 1.0;
  for (int s = 0; s < model.num_frames; ++s) {
    for (int t = s + 1; t < model.num_frames; ++t) {
      const double cosine = 0.5 * (rotations[t].cwiseProduct(rotations[s]).sum() - 1.0);
      smallest_cosine = std::min(smallest_cosine, cosine);
    }
  }
  return std::acos(std::clamp(smallest_cosine, -1.0, 1.0)) * kDegreesPerRadian;
}

}  // namespace nrsfm
