#include "solvers/prior_rule.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/option_checker.h"
#include "core/rotation.h"
#include "problems/extra_terms.h"

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
  check.Require(std::isfinite(min_track_order) && min_track_order > 1.0,
                "min_track_order must be > 1 (frames in no order have a ratio near 1), got " +
                    std::to_string(min_track_order));
  check.FinitePositive("min_basis_fraction", min_basis_fraction);
  check.FinitePositive("temporal_shape_weight", temporal_shape_weight);
  check.FiniteAtLeast("max_path_acceleration_deg", max_path_acceleration_deg, 0.0);
  check.FinitePositive("rotation_acceleration_weight", rotation_acceleration_weight);
  return check.status();
}

double MedianTrackStep(const Measurements& measurements, int lag) {
  const double spread = measurements.ImageSpreadRms();
  if (!(spread > 0.0) || lag < 1) return -1.0;
  std::vector<double> steps;
  for (int t = lag; t < measurements.num_frames; ++t) {
    double sum = 0.0;
    int count = 0;
    for (int c = 0; c < measurements.num_cameras; ++c) {
      const int view = measurements.View(t, c);
      const int previous = measurements.View(t - lag, c);
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

double TrackOrder(const Measurements& measurements) {
  const double step = MedianTrackStep(measurements, 1);
  if (measurements.num_frames < 8 || !(step > 0.0)) return -1.0;
  double order = -1.0;
  for (int lag = 2; lag <= measurements.num_frames / 2; lag *= 2) {
    order = std::max(order, MedianTrackStep(measurements, lag) / step);
  }
  return order;
}

double MedianPathAccelerationDeg(const Model& model, int lag) {
  if (lag < 1 || model.num_frames < 2 * lag + 1) return -1.0;
  std::vector<double> accelerations;
  accelerations.reserve(model.num_frames - 2 * lag);
  const double lag2 = static_cast<double>(lag) * lag;
  for (int t = lag; t + lag < model.num_frames; ++t) {
    const Eigen::Vector3d before =
        RotationToAngleAxis(model.Rotation(t, 0) * model.Rotation(t - lag, 0).transpose());
    const Eigen::Vector3d after =
        RotationToAngleAxis(model.Rotation(t + lag, 0) * model.Rotation(t, 0).transpose());
    accelerations.push_back((after - before).norm() / lag2 * kDegreesPerRadian);
  }
  return Median(std::move(accelerations));
}

double PathAccelerationDeg(const Model& model) {
  constexpr int kLag = 4;
  const double long_lag = MedianPathAccelerationDeg(model, kLag);
  if (long_lag < 0.0) return -1.0;
  return std::max(0.0, long_lag - MedianPathAccelerationDeg(model, 1) / (kLag * kLag));
}

void DecideVideoPriors(const PriorRuleOptions& options,
                       const Measurements& measurements, int num_bases,
                       PriorDecision* decision) {
  decision->track_step = MedianTrackStep(measurements);
  decision->track_order = TrackOrder(measurements);
  decision->video = decision->track_order >= options.min_track_order;
  const bool basis_absorbs_rotation =
      3.0 * num_bases >= options.min_basis_fraction * measurements.num_points;
  if (decision->video && basis_absorbs_rotation) {
    decision->term_weights[kTemporalShapeTerm] = options.temporal_shape_weight;
  }
}

void DecidePathPrior(const PriorRuleOptions& options, const Model& start,
                     PriorDecision* decision) {
  if (decision->term_weights.count(kTemporalShapeTerm) == 0) return;
  decision->path_acceleration_deg = PathAccelerationDeg(start);
  const bool constant_angular_velocity =
      decision->path_acceleration_deg >= 0.0 &&
      decision->path_acceleration_deg < options.max_path_acceleration_deg;
  if (constant_angular_velocity) {
    decision->term_weights[kRotationAccelerationTerm] =
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
