#include "core/synthetic/synthetic_common.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <limits>
#include <numeric>
#include <vector>

namespace nrsfm {
namespace synthetic {

SmoothCurve RandomCurve(Random* random, double min_cycles, double max_cycles) {
  SmoothCurve curve;
  curve.cycles1 = random->Uniform(min_cycles, max_cycles);
  curve.cycles2 = curve.cycles1 * random->Uniform(1.0, 2.0);
  curve.phase1 = random->Uniform(0.0, 2.0 * kPi);
  curve.phase2 = random->Uniform(0.0, 2.0 * kPi);
  return curve;
}

double Tau(int frame, int num_frames) {
  return static_cast<double>(frame) / static_cast<double>(num_frames - 1);
}

Eigen::Matrix3d AxisRotation(int axis, double angle) {
  return Eigen::AngleAxisd(angle, Eigen::Vector3d::Unit(axis))
      .toRotationMatrix();
}

double SmoothStep(double edge0, double edge1, double x) {
  const double u = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
  return u * u * (3.0 - 2.0 * u);
}

double SmoothStepDerivative(double edge0, double edge1, double x) {
  const double u = (x - edge0) / (edge1 - edge0);
  if (u <= 0.0 || u >= 1.0) return 0.0;
  return 6.0 * u * (1.0 - u) / (edge1 - edge0);
}

double SignedPower(double c, double e) {
  return std::copysign(std::pow(std::abs(c), e), c);
}

void SetSmoothRotations(double max_rotation_deg, Random* motion, Model* truth) {
  const double amplitude = 0.5 * max_rotation_deg * kDegToRad;
  SmoothCurve curves[3];
  for (SmoothCurve& curve : curves) curve = RandomCurve(motion, 0.5, 1.5);
  for (int t = 0; t < truth->num_frames; ++t) {
    const double tau = Tau(t, truth->num_frames);
    truth->SetRotation(t, 0,
                       AxisRotation(2, amplitude * curves[2](tau)) *
                           AxisRotation(1, amplitude * curves[1](tau)) *
                           AxisRotation(0, amplitude * curves[0](tau)));
  }
}

void CentreBasis(Model* truth) {
  for (int k = 0; k < truth->num_bases; ++k) {
    const Eigen::Matrix3Xd shape = truth->BasisShape(k);
    truth->SetBasisShape(k, shape.colwise() - shape.rowwise().mean());
  }
}

VisibilityMask RandomMissing(int num_views, int num_points, double fraction,
                             Random* random) {
  VisibilityMask visible =
      VisibilityMask::Constant(num_views, num_points, true);
  RemoveAtRandom(fraction, random, &visible);
  return visible;
}

void RemoveAtRandom(double fraction, Random* random, VisibilityMask* visible) {
  const int num_views = static_cast<int>(visible->rows());
  const int num_points = static_cast<int>(visible->cols());
  const int total = num_views * num_points;
  const int target = static_cast<int>(std::lround(fraction * total));
  if (target == 0) return;
  std::vector<int> order(total);
  std::iota(order.begin(), order.end(), 0);
  for (int i = total - 1; i > 0; --i)
    std::swap(order[i], order[random->Index(i + 1)]);
  Eigen::VectorXi per_view = visible->rowwise().count().cast<int>();
  Eigen::VectorXi per_point =
      visible->colwise().count().transpose().cast<int>();
  int removed = 0;
  for (int i = 0; i < total && removed < target; ++i) {
    const int view = order[i] / num_points;
    const int point = order[i] % num_points;
    if (!(*visible)(view, point)) continue;
    if (per_view(view) <= 2 || per_point(point) <= 2) continue;
    (*visible)(view, point) = false;
    --per_view(view);
    --per_point(point);
    ++removed;
  }
}

void FillMeasurements(const Model& truth, const VisibilityMask& visible,
                      double noise_stddev, std::uint64_t seed,
                      Measurements* measurements) {
  Random noise(seed, kNoiseStream);
  Measurements& m = *measurements;
  m.num_frames = truth.num_frames;
  m.num_cameras = truth.num_cameras;
  m.num_points = truth.num_points;
  m.W.resize(2 * m.NumViews(), m.num_points);
  m.visible = visible;
  for (int t = 0; t < m.num_frames; ++t) {
    for (int c = 0; c < m.num_cameras; ++c) {
      const Eigen::Matrix2Xd projected = truth.Project(t, c);
      const int row = m.Row(t, c);
      for (int p = 0; p < m.num_points; ++p) {
        for (int i = 0; i < 2; ++i) {
          // Drawn for every entry so the noise does not depend on the mask.
          const double n =
              noise_stddev > 0.0 ? noise_stddev * noise.Normal() : 0.0;
          m.W(row + i, p) = m.visible(m.View(t, c), p)
                                ? projected(i, p) + n
                                : std::numeric_limits<double>::quiet_NaN();
        }
      }
    }
  }
}

// ---- Shoe geometry (object frame: x from heel −0.5 to toe +0.5, y up, the
// sole at y = kSoleY, z lateral (−) to medial (+); camera 0 at rest looks

void CheckSmoothSequence(const SmoothSequenceOptions& options,
                         OptionChecker* check) {
  check->AtLeast("num_frames", options.num_frames, 2);
  check->InRange("max_rotation_deg", options.max_rotation_deg, 0.0, 360.0,
                 false);
  check->FiniteAtLeast("noise_stddev", options.noise_stddev, 0.0);
  check->InRange("missing_fraction", options.missing_fraction, 0.0, 1.0, true);
}

void FinishSmoothSequence(const SmoothSequenceOptions& options,
                          SyntheticSequence* sequence) {
  const Model& truth = sequence->truth;
  Random missing(options.seed, kMissingStream);
  FillMeasurements(truth,
                   RandomMissing(truth.NumViews(), truth.num_points,
                                 options.missing_fraction, &missing),
                   options.noise_stddev, options.seed, &sequence->measurements);
}

}  // namespace synthetic
}  // namespace nrsfm
