#include <glog/logging.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/model/enum_names.h"
#include "core/model/option_checker.h"
#include "core/synthetic/synthetic.h"
#include "core/synthetic/synthetic_common.h"

namespace nrsfm {
namespace {

constexpr EnumName<SpeedProfile> kSpeedProfileNames[] = {
    {SpeedProfile::kConstant, "constant"},
    {SpeedProfile::kRamp, "ramp"},
    {SpeedProfile::kStopAndGo, "stopgo"},
};

// Segments of the stop-and-go profile (moving, standing, moving, …).
constexpr int kStopAndGoSegments = 8;

// θ / Θ at τ ∈ [0, 1].
double AngleFraction(SpeedProfile profile, double tau) {
  switch (profile) {
    case SpeedProfile::kConstant:
      return tau;
    case SpeedProfile::kRamp:
      return tau * tau;
    case SpeedProfile::kStopAndGo: {
      // Time spent moving up to τ over the whole time spent moving.
      const double segment = 1.0 / kStopAndGoSegments;
      double moving = 0.0;
      for (int s = 0; s < kStopAndGoSegments; s += 2) {
        const double begin = s * segment;
        moving += std::clamp(tau - begin, 0.0, segment);
      }
      return moving / (0.5 * kStopAndGoSegments * segment);
    }
  }
  return tau;
}

// Hides (t, p) when another point of frame t lies within `radius` of it in
// the image and at least `radius` nearer the camera (smaller z: the camera
// looks along +z). Then shows again, for every point and frame left with
// fewer than 2 entries, its least hidden entries (smallest depth margin).
VisibilityMask SelfOcclusion(const std::vector<Eigen::Matrix3Xd>& in_camera,
                             double radius) {
  const int num_frames = static_cast<int>(in_camera.size());
  const int num_points = static_cast<int>(in_camera[0].cols());
  VisibilityMask visible =
      VisibilityMask::Constant(num_frames, num_points, true);
  // How far behind its nearest occluder each hidden entry is (> 0).
  Eigen::ArrayXXd margin = Eigen::ArrayXXd::Zero(num_frames, num_points);
  for (int t = 0; t < num_frames; ++t) {
    const Eigen::Matrix3Xd& x = in_camera[t];
    for (int p = 0; p < num_points; ++p) {
      for (int q = 0; q < num_points; ++q) {
        if (q == p) continue;
        if ((x.col(q).head<2>() - x.col(p).head<2>()).norm() >= radius)
          continue;
        const double behind = x(2, p) - x(2, q) - radius;
        if (behind >= 0.0) {
          visible(t, p) = false;
          margin(t, p) = std::max(margin(t, p), behind + 1e-12);
        }
      }
    }
  }
  auto show_least_hidden = [&](bool per_point, int index) {
    const int count = per_point ? num_frames : num_points;
    std::vector<std::pair<double, int>> hidden;
    int shown = 0;
    for (int i = 0; i < count; ++i) {
      const int t = per_point ? i : index, p = per_point ? index : i;
      if (visible(t, p)) {
        ++shown;
      } else {
        hidden.emplace_back(margin(t, p), i);
      }
    }
    std::sort(hidden.begin(), hidden.end());
    for (std::size_t j = 0; shown < 2 && j < hidden.size(); ++j, ++shown) {
      const int i = hidden[j].second;
      visible(per_point ? i : index, per_point ? index : i) = true;
    }
  };
  for (int p = 0; p < num_points; ++p) show_least_hidden(true, p);
  for (int t = 0; t < num_frames; ++t) show_least_hidden(false, t);
  return visible;
}

}  // namespace

const char* SpeedProfileName(SpeedProfile profile) {
  return NameOf(kSpeedProfileNames, profile);
}

Status ParseSpeedProfile(const std::string& name, SpeedProfile* profile) {
  return ParseName(kSpeedProfileNames, name, "speed profile", profile);
}

Status ReprojectOptions::Check() const {
  OptionChecker check("ReprojectOptions");
  check.InRange("total_rotation_deg", total_rotation_deg, 0.0, 3600.0);
  check.Require(total_rotation_deg > 0.0,
                "total_rotation_deg must be > 0 (without rotation the depth is "
                "unobservable)");
  check.Require(axis.allFinite() && axis.norm() > 0.0,
                "axis must be a finite, non-zero direction");
  check.InRange("noise_fraction", noise_fraction, 0.0, 1.0, true);
  check.InRange("missing_fraction", missing_fraction, 0.0, 1.0, true);
  check.InRange("occlusion_radius", occlusion_radius, 0.0, 1.0, true);
  check.InRange("distance_ratio", distance_ratio, 0.0, 1e6);
  check.Require(distance_ratio == 0.0 || occlusion_radius == 0.0,
                "occlusion_radius is for the orthographic camera only "
                "(distance_ratio 0)");
  return check.status();
}

Status GenerateReprojection(const GroundTruth& source,
                            const ReprojectOptions& options,
                            ReprojectedSequence* sequence) {
  CHECK(sequence != nullptr);
  NRSFM_RETURN_IF_ERROR(options.Check());
  const int num_frames = source.NumFrames();
  const int num_points = source.NumPoints();
  if (num_frames < 2 || num_points < 1) {
    return Status::Error("re-projection: the source '" + source.source +
                         "' has F = " + std::to_string(num_frames) +
                         ", P = " + std::to_string(num_points) +
                         "; needs at least 2 frames and 1 point");
  }
  const bool object_frame = source.HasObjectFrame();
  const Eigen::Matrix3d base =
      object_frame ? source.rotations[0] : Eigen::Matrix3d::Identity();
  const Eigen::Vector3d axis = options.axis.normalized();
  const double total = options.total_rotation_deg * synthetic::kDegToRad;

  GroundTruth& truth = sequence->truth;
  truth = GroundTruth();
  truth.source = "S+Rs";
  truth.points_in_object =
      object_frame ? source.points_in_object : source.points_in_camera;
  truth.rotations.resize(num_frames);
  truth.points_in_camera.resize(num_frames);
  sequence->image_size = 0.0;
  const bool pinhole = options.distance_ratio > 0.0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Vector3d low =
      Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d high = -low;
  for (const Eigen::Matrix3Xd& shape : truth.points_in_object) {
    mean += shape.rowwise().sum();
    low = low.cwiseMin(shape.rowwise().minCoeff());
    high = high.cwiseMax(shape.rowwise().maxCoeff());
  }
  mean /= static_cast<double>(num_frames) * num_points;
  const double distance = options.distance_ratio * (high - low).maxCoeff();
  const double focal = kPinholeImagePixels * options.distance_ratio;
  const double centre = kPinholeImagePixels;
  std::vector<Eigen::Matrix2Xd> images(num_frames);
  for (int t = 0; t < num_frames; ++t) {
    const double theta =
        total * AngleFraction(options.profile, synthetic::Tau(t, num_frames));
    truth.rotations[t] =
        Eigen::AngleAxisd(theta, axis).toRotationMatrix() * base;
    Eigen::Matrix3Xd& x = truth.points_in_camera[t];
    x = truth.rotations[t] * truth.points_in_object[t];
    if (pinhole) {
      x.colwise() +=
          Eigen::Vector3d(0.0, 0.0, distance) - truth.rotations[t] * mean;
      if (!(x.row(2).minCoeff() > 0.0)) {
        return Status::Error("re-projection: distance_ratio " +
                             std::to_string(options.distance_ratio) +
                             " puts a point of frame " + std::to_string(t) +
                             " at or behind the camera");
      }
      images[t].resize(2, num_points);
      images[t].row(0) =
          (focal * x.row(0).cwiseQuotient(x.row(2))).array() + centre;
      images[t].row(1) =
          (focal * x.row(1).cwiseQuotient(x.row(2))).array() + centre;
    } else {
      images[t] = x.topRows<2>();
    }
    const Eigen::Vector2d extent =
        images[t].rowwise().maxCoeff() - images[t].rowwise().minCoeff();
    sequence->image_size = std::max(sequence->image_size, extent.maxCoeff());
  }
  sequence->noise_stddev = options.noise_fraction * sequence->image_size;

  VisibilityMask visible =
      options.occlusion_radius > 0.0
          ? SelfOcclusion(truth.points_in_camera,
                          options.occlusion_radius * sequence->image_size)
          : VisibilityMask::Constant(num_frames, num_points, true);
  Random missing(options.seed, synthetic::kMissingStream);
  synthetic::RemoveAtRandom(options.missing_fraction, &missing, &visible);

  Random noise(options.seed, synthetic::kNoiseStream);
  Measurements& m = sequence->measurements;
  m = Measurements();
  m.num_frames = num_frames;
  m.num_cameras = 1;
  m.num_points = num_points;
  m.W.resize(2 * num_frames, num_points);
  m.visible = visible;
  if (pinhole) {
    m.intrinsics.resize(4, 1);
    m.intrinsics.col(0) << focal, focal, centre, centre;
  }
  for (int t = 0; t < num_frames; ++t) {
    for (int p = 0; p < num_points; ++p) {
      // Noise is drawn for every entry, so it does not depend on which are
      // missing.
      const double du = sequence->noise_stddev * noise.Normal();
      const double dv = sequence->noise_stddev * noise.Normal();
      const Eigen::Vector2d x = images[t].col(p);
      if (visible(t, p)) {
        m.W(2 * t, p) = x(0) + du;
        m.W(2 * t + 1, p) = x(1) + dv;
      } else {
        m.W(2 * t, p) = m.W(2 * t + 1, p) =
            std::numeric_limits<double>::quiet_NaN();
      }
    }
  }
  return Status::OK();
}

}  // namespace nrsfm
