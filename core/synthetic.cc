#include "core/synthetic.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <numeric>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <glog/logging.h>

#include "core/option_checker.h"
#include "core/random.h"

namespace nrsfm {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;

// Independent random streams of one seed: changing the noise or the missing
// fraction leaves the geometry and motion of a sequence unchanged.
enum Stream : std::uint64_t {
  kGeometryStream = 1,
  kMotionStream = 2,
  kNoiseStream = 3,
  kMissingStream = 4,
};

// A smooth signal in [−1, 1] over tau ∈ [0, 1]: two sinusoids of random phase
// with `min_cycles`…`max_cycles` and 1…2 times that many cycles.
struct SmoothCurve {
  double cycles1, cycles2, phase1, phase2;
  double operator()(double tau) const {
    return 0.6 * std::sin(2.0 * kPi * cycles1 * tau + phase1) +
           0.4 * std::sin(2.0 * kPi * cycles2 * tau + phase2);
  }
};

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

// sign(c)·|c|^e: the signed power of the superquadric parametrisation.
double SignedPower(double c, double e) {
  return std::copysign(std::pow(std::abs(c), e), c);
}

// R_t = Rz(c_t) Ry(b_t) Rx(a_t), each angle max_rotation_deg / 2 · curve(τ):
// the rotations shared by the random-basis and superquadric data.
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

// Subtracts from every basis shape its mean over the points, so every S_t is
// centred and, with zero translations, so is every complete frame of W.
void CentreBasis(Model* truth) {
  for (int k = 0; k < truth->num_bases; ++k) {
    const Eigen::Matrix3Xd shape = truth->BasisShape(k);
    truth->SetBasisShape(k, shape.colwise() - shape.rowwise().mean());
  }
}

// All visible, then `fraction` of the entries removed in random order, skipping
// any removal that would leave a view or a point with fewer than 2 entries.
VisibilityMask RandomMissing(int num_views, int num_points, double fraction,
                             Random* random) {
  VisibilityMask visible =
      VisibilityMask::Constant(num_views, num_points, true);
  const int total = num_views * num_points;
  const int target = static_cast<int>(std::lround(fraction * total));
  if (target == 0) return visible;
  std::vector<int> order(total);
  std::iota(order.begin(), order.end(), 0);
  for (int i = total - 1; i > 0; --i)
    std::swap(order[i], order[random->Index(i + 1)]);
  Eigen::VectorXi per_view = Eigen::VectorXi::Constant(num_views, num_points);
  Eigen::VectorXi per_point = Eigen::VectorXi::Constant(num_points, num_views);
  int removed = 0;
  for (int i = 0; i < total && removed < target; ++i) {
    const int view = order[i] / num_points;
    const int point = order[i] % num_points;
    if (per_view(view) <= 2 || per_point(point) <= 2) continue;
    visible(view, point) = false;
    --per_view(view);
    --per_point(point);
    ++removed;
  }
  return visible;
}

// W = truth.Project(t, c) plus N(0, noise²) on the visible entries, NaN on
// the others.
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
// along +z at the lateral side, from above once pitched).
constexpr double kHalfLength = 0.5;
constexpr double kSoleY = -0.11;
constexpr double kSuperExponent =
    0.5;                           // e; the unit surface is Σ|u_i|^(2/e) = 1.
constexpr double kRigScale = 0.9;  // s_t1 / s_t0

// Half height (heel raised, toe low) and half width (tapered toe) at x, and
// their derivatives.
double HalfHeight(double x) {
  return 0.11 + 0.05 * (1.0 - SmoothStep(-0.35, 0.05, x)) -
         0.04 * SmoothStep(0.15, 0.5, x);
}
double HalfHeightDerivative(double x) {
  return -0.05 * SmoothStepDerivative(-0.35, 0.05, x) -
         0.04 * SmoothStepDerivative(0.15, 0.5, x);
}
double HalfWidth(double x) {
  return 0.16 - 0.06 * SmoothStep(0.1, 0.5, x) -
         0.02 * (1.0 - SmoothStep(-0.5, -0.25, x));
}
double HalfWidthDerivative(double x) {
  return -0.06 * SmoothStepDerivative(0.1, 0.5, x) +
         0.02 * SmoothStepDerivative(-0.5, -0.25, x);
}

// Point and outward unit normal of the shoe at surface coordinates
// (s, theta): s ∈ (−1, 1) runs from heel to toe, theta is the direction of
// the point in the cross-section (0 = up, −π/2 = lateral). On the unit
// superellipsoid g(u) = Σ|u_i|^m = 1 (m = 2/e) the point is
//   u = (s, ρ r(θ) cos θ, ρ r(θ) sin θ),  ρ = (1 − |s|^m)^(1/m),
//   r(θ) = (|cos θ|^m + |sin θ|^m)^(−1/m);
// it is mapped by φ(u) = (A u1, h(x) u2 + h(x) + kSoleY, w(x) u3), x = A u1,
// and the normal is J⁻ᵀ ∇g(u), J = ∂φ/∂u.
void ShoeSurface(double s, double theta, Eigen::Vector3d* point,
                 Eigen::Vector3d* normal) {
  const double m = 2.0 / kSuperExponent;
  const double c = std::cos(theta), d = std::sin(theta);
  const double rho = std::pow(1.0 - std::pow(std::abs(s), m), 1.0 / m);
  const double r =
      std::pow(std::pow(std::abs(c), m) + std::pow(std::abs(d), m), -1.0 / m);
  const Eigen::Vector3d u(s, rho * r * c, rho * r * d);
  const double x = kHalfLength * u(0);
  const double h = HalfHeight(x), dh = HalfHeightDerivative(x);
  const double w = HalfWidth(x), dw = HalfWidthDerivative(x);
  *point = Eigen::Vector3d(x, h * u(1) + h + kSoleY, w * u(2));
  Eigen::Matrix3d jacobian;
  jacobian << kHalfLength, 0.0, 0.0,            //
      kHalfLength * dh * (u(1) + 1.0), h, 0.0,  //
      kHalfLength * dw * u(2), 0.0, w;
  Eigen::Vector3d gradient;
  for (int i = 0; i < 3; ++i) gradient(i) = SignedPower(u(i), m - 1.0);
  *normal = jacobian.transpose().inverse() * gradient;
  normal->normalize();
}

// Surface coordinates (s, θ) of the shoe's points, edges first (evenly
// spaced along the long edges and the toe and heel loops), then six corners
// and random texture on the lateral side and top.
std::vector<Eigen::Vector2d> ShoeParameters(int num_points, Random* geometry) {
  const int num_texture =
      static_cast<int>(std::lround(num_points * 30.0 / 110.0));
  const int num_edge = num_points - num_texture;
  struct Edge {
    double s0, s1, theta0, theta1;
    int share;  // relative number of points
  };
  const double q = 0.25 * kPi;
  const double loop = 0.84;  // |s| of the toe and heel loops
  const Edge edges[] = {
      {-0.95, 0.95, -q, -q, 24},        // top-lateral long edge
      {-0.9, 0.9, -3 * q, -3 * q, 16},  // bottom-lateral long edge
      {-0.9, 0.9, q, q, 12},            // top-medial long edge
      {loop, loop, -3 * q, q, 14},      // toe loop, lateral side and top
      {-loop, -loop, -3 * q, q, 14},    // heel loop, lateral side and top
  };
  int share_sum = 0;
  for (const Edge& edge : edges) share_sum += edge.share;
  std::vector<Eigen::Vector2d> params;
  int assigned = 0;
  for (size_t i = 0; i < std::size(edges); ++i) {
    const int count = i + 1 == std::size(edges)
                          ? num_edge - assigned
                          : num_edge * edges[i].share / share_sum;
    assigned += count;
    for (int j = 0; j < count; ++j) {
      const double a = (j + 0.5) / count;
      params.emplace_back(
          edges[i].s0 + a * (edges[i].s1 - edges[i].s0),
          edges[i].theta0 + a * (edges[i].theta1 - edges[i].theta0));
    }
  }
  const Eigen::Vector2d corners[] = {{loop, -3 * q},  {loop, -q},  {loop, q},
                                     {-loop, -3 * q}, {-loop, -q}, {-loop, q}};
  for (int i = 0; i < num_texture; ++i) {
    if (i < static_cast<int>(std::size(corners))) {
      params.push_back(corners[i]);
    } else {
      const double s = geometry->Uniform(-0.9, 0.9);
      params.emplace_back(s, geometry->Uniform(-3 * q + 0.2, q - 0.2));
    }
  }
  return params;
}

}  // namespace

Status RandomBasisOptions::Check() const {
  OptionChecker check("RandomBasisOptions");
  check.AtLeast("num_frames", num_frames, 2);
  check.AtLeast("num_points", num_points, 1);
  check.AtLeast("num_bases", num_bases, 1);
  check.FiniteAtLeast("deformation", deformation, 0.0);
  check.InRange("max_rotation_deg", max_rotation_deg, 0.0, 360.0, false);
  check.FiniteAtLeast("noise_stddev", noise_stddev, 0.0);
  check.InRange("missing_fraction", missing_fraction, 0.0, 1.0, true);
  return check.status();
}

Status GenerateRandomBasis(const RandomBasisOptions& options,
                           SyntheticSequence* sequence) {
  CHECK(sequence != nullptr);
  NRSFM_RETURN_IF_ERROR(options.Check());
  Random geometry(options.seed, kGeometryStream);
  Random motion(options.seed, kMotionStream);
  Random missing(options.seed, kMissingStream);
  Model& truth = sequence->truth;
  truth.Resize(options.num_frames, 1, options.num_points, options.num_bases);
  for (int k = 0; k < options.num_bases; ++k) {
    Eigen::Matrix3Xd shape(3, options.num_points);
    for (int p = 0; p < options.num_points; ++p) {
      for (int i = 0; i < 3; ++i) shape(i, p) = geometry.Uniform(-0.5, 0.5);
    }
    truth.SetBasisShape(k, shape);
  }
  CentreBasis(&truth);
  SetSmoothRotations(options.max_rotation_deg, &motion, &truth);
  for (int t = 0; t < options.num_frames; ++t) {
    truth.weights(0, t) = 1.0;
    for (int k = 1; k < options.num_bases; ++k) {
      truth.weights(k, t) = options.deformation * motion.Normal();
    }
  }
  FillMeasurements(truth,
                   RandomMissing(truth.NumViews(), truth.num_points,
                                 options.missing_fraction, &missing),
                   options.noise_stddev, options.seed, &sequence->measurements);
  return Status::OK();
}

Status SuperquadricOptions::Check() const {
  OptionChecker check("SuperquadricOptions");
  check.AtLeast("num_frames", num_frames, 2);
  check.AtLeast("num_points", num_points, 1);
  check.InRange("max_rotation_deg", max_rotation_deg, 0.0, 360.0, false);
  check.FiniteAtLeast("noise_stddev", noise_stddev, 0.0);
  check.InRange("missing_fraction", missing_fraction, 0.0, 1.0, true);
  return check.status();
}

Status GenerateSuperquadric(const SuperquadricOptions& options,
                            SyntheticSequence* sequence) {
  CHECK(sequence != nullptr);
  NRSFM_RETURN_IF_ERROR(options.Check());
  constexpr double kSemiAxes[3] = {0.5, 0.4, 0.3};
  constexpr double kExponent = 0.5;
  // The deforming octants (signs of x, y, z).
  constexpr double kOctants[3][3] = {{1, 1, 1}, {-1, -1, 1}, {1, -1, -1}};
  Random geometry(options.seed, kGeometryStream);
  Random motion(options.seed, kMotionStream);
  Random missing(options.seed, kMissingStream);
  Model& truth = sequence->truth;
  truth.Resize(options.num_frames, 1, options.num_points, 4);
  Eigen::Matrix3Xd rest(3, options.num_points);
  for (int p = 0; p < options.num_points; ++p) {
    // asin of a uniform: area-uniform on a sphere, roughly so on the surface.
    const double eta = std::asin(geometry.Uniform(-1.0, 1.0));
    const double omega = geometry.Uniform(-kPi, kPi);
    const double c = SignedPower(std::cos(eta), kExponent);
    rest.col(p) << kSemiAxes[0] * c * SignedPower(std::cos(omega), kExponent),
        kSemiAxes[1] * c * SignedPower(std::sin(omega), kExponent),
        kSemiAxes[2] * SignedPower(std::sin(eta), kExponent);
  }
  truth.SetBasisShape(0, rest);
  for (int o = 0; o < 3; ++o) {
    // Radial scaling of the octant, faded smoothly to 0 at its three planes.
    Eigen::Matrix3Xd mode(3, options.num_points);
    for (int p = 0; p < options.num_points; ++p) {
      double falloff = 1.0;
      for (int i = 0; i < 3; ++i) {
        falloff *=
            SmoothStep(0.0, 0.5, kOctants[o][i] * rest(i, p) / kSemiAxes[i]);
      }
      mode.col(p) = falloff * rest.col(p);
    }
    truth.SetBasisShape(o + 1, mode);
  }
  CentreBasis(&truth);
  SetSmoothRotations(options.max_rotation_deg, &motion, &truth);
  for (int o = 0; o < 3; ++o) {
    const SmoothCurve curve = RandomCurve(&motion, 1.0, 3.0);
    for (int t = 0; t < options.num_frames; ++t) {
      truth.weights(0, t) = 1.0;
      truth.weights(o + 1, t) = 0.5 * curve(Tau(t, options.num_frames));
    }
  }
  FillMeasurements(truth,
                   RandomMissing(truth.NumViews(), truth.num_points,
                                 options.missing_fraction, &missing),
                   options.noise_stddev, options.seed, &sequence->measurements);
  return Status::OK();
}

Status ShoeOptions::Check() const {
  OptionChecker check("ShoeOptions");
  check.AtLeast("num_frames", num_frames, 2);
  check.AtLeast("num_points", num_points, 10);
  check.InRange("num_cameras", num_cameras, 1, 2, false);
  check.InRange("camera_baseline_deg", camera_baseline_deg, -90.0, 90.0, false);
  check.FiniteAtLeast("noise_stddev", noise_stddev, 0.0);
  return check.status();
}

Status GenerateShoe(const ShoeOptions& options, SyntheticSequence* sequence) {
  CHECK(sequence != nullptr);
  NRSFM_RETURN_IF_ERROR(options.Check());
  const int num_frames = options.num_frames;
  const int num_points = options.num_points;
  const int num_cameras = options.num_cameras;
  Random geometry(options.seed, kGeometryStream);
  Random motion(options.seed, kMotionStream);
  Model& truth = sequence->truth;
  truth.Resize(num_frames, num_cameras, num_points, 4);

  const std::vector<Eigen::Vector2d> params =
      ShoeParameters(num_points, &geometry);
  Eigen::Matrix3Xd rest(3, num_points), normals(3, num_points);
  for (int p = 0; p < num_points; ++p) {
    Eigen::Vector3d point, normal;
    ShoeSurface(params[p](0), params[p](1), &point, &normal);
    rest.col(p) = point;
    normals.col(p) = normal;
  }
  // Deformation modes (displacement per unit weight). Each is a non-linear
  // field with three independent rows, so that noise-free W has the full rank
  // 3K (+1 for the translations): a pure rotation field has rank 2 and a
  // linear map of the rest shape is absorbed by the camera.
  //   toe bend  — linearised rotation about z through the ball of the foot,
  //               faded in over the toe, with a slight widening of the toe;
  //   sole flex — linearised bending of the whole shoe about the sole line,
  //               widening where it bends;
  //   squash    — vertical compression with a forward push and a lateral
  //               bulge of the upper, strongest at the heel.
  const Eigen::Vector2d ball(0.15, kSoleY);
  Eigen::Matrix3Xd toe(3, num_points), flex(3, num_points),
      squash(3, num_points);
  for (int p = 0; p < num_points; ++p) {
    const double x = rest(0, p), y = rest(1, p), z = rest(2, p);
    const double height = y - kSoleY;
    toe.col(p) = SmoothStep(0.05, 0.3, x) *
                 Eigen::Vector3d(-(y - ball(1)), x - ball(0), 0.3 * z);
    flex.col(p) << -x * height, 0.5 * x * x, 0.3 * x * x * z;
    squash.col(p) =
        (1.0 - 0.5 * SmoothStep(-0.5, 0.5, x)) *
        Eigen::Vector3d(0.3 * height * height, -height, 3.0 * z * height);
  }
  truth.SetBasisShape(0, rest);
  truth.SetBasisShape(1, toe);
  truth.SetBasisShape(2, flex);
  truth.SetBasisShape(3, squash);
  CentreBasis(&truth);

  // Motion: yaw about the vertical axis up to ±60°, pitch −28° ± 18° (the
  // camera looks down on the shoe), roll ±20°; smooth weights.
  const SmoothCurve yaw = RandomCurve(&motion, 0.5, 1.5);
  const SmoothCurve pitch = RandomCurve(&motion, 0.5, 1.5);
  const SmoothCurve roll = RandomCurve(&motion, 0.5, 1.5);
  const SmoothCurve toe_curve = RandomCurve(&motion, 1.0, 4.0);
  const SmoothCurve flex_curve = RandomCurve(&motion, 1.0, 4.0);
  const SmoothCurve squash_curve = RandomCurve(&motion, 1.0, 4.0);
  SmoothCurve shift[2][2];
  for (auto& view_shift : shift) {
    for (SmoothCurve& curve : view_shift)
      curve = RandomCurve(&motion, 0.5, 2.0);
  }
  const Eigen::Matrix3d rig =
      AxisRotation(1, options.camera_baseline_deg * kDegToRad);
  if (num_cameras == 2) {
    truth.rig_rotations.col(0) << 0.0, options.camera_baseline_deg * kDegToRad,
        0.0;
    truth.rig_scales(0) = kRigScale;
  }
  // Camera 0 sees yaws centred on −baseline / 2, camera 1 on +baseline / 2.
  const double yaw_offset =
      num_cameras == 2 ? -0.5 * options.camera_baseline_deg * kDegToRad : 0.0;
  for (int t = 0; t < num_frames; ++t) {
    const double tau = Tau(t, num_frames);
    truth.weights.col(t) << 1.0, 0.25 + 0.25 * toe_curve(tau),
        0.6 * flex_curve(tau), 0.1 * squash_curve(tau);
    const Eigen::Matrix3d r0 =
        AxisRotation(0, (-28.0 + 18.0 * pitch(tau)) * kDegToRad) *
        AxisRotation(2, 20.0 * kDegToRad * roll(tau)) *
        AxisRotation(1, yaw_offset + 60.0 * kDegToRad * yaw(tau));
    truth.SetRotation(t, 0, r0);
    if (num_cameras == 2) {
      truth.SetRotation(t, 1, rig * r0);
      truth.scales(truth.View(t, 1)) = kRigScale;
    }
    for (int c = 0; c < num_cameras; ++c) {
      truth.translations.col(truth.View(t, c)) << 0.2 * shift[c][0](tau),
          0.2 * shift[c][1](tau);
    }
  }

  // Self-occlusion: the camera looks along +z, so a point is visible when its
  // rotated rest normal has z < 0. Every view keeps at least 4 points and
  // every point at least one observation (the most camera-facing ones).
  VisibilityMask visible =
      VisibilityMask::Constant(truth.NumViews(), num_points, true);
  if (options.self_occlusion) {
    Eigen::MatrixXd facing(truth.NumViews(), num_points);  // z of R n
    for (int view = 0; view < truth.NumViews(); ++view) {
      facing.row(view) =
          (truth.Rotation(view / num_cameras, view % num_cameras) * normals)
              .row(2);
    }
    visible = facing.array() < 0.0;
    constexpr int kMinPerView = 4;
    for (int view = 0; view < truth.NumViews(); ++view) {
      while (visible.row(view).count() < std::min(kMinPerView, num_points)) {
        Eigen::Index best = 0;
        double best_facing = std::numeric_limits<double>::infinity();
        for (int p = 0; p < num_points; ++p) {
          if (!visible(view, p) && facing(view, p) < best_facing) {
            best_facing = facing(view, p);
            best = p;
          }
        }
        visible(view, best) = true;
      }
    }
    for (int p = 0; p < num_points; ++p) {
      if (visible.col(p).any()) continue;
      Eigen::Index best_view = 0;
      facing.col(p).minCoeff(&best_view);
      visible(best_view, p) = true;
    }
  }
  FillMeasurements(truth, visible, options.noise_stddev, options.seed,
                   &sequence->measurements);
  return Status::OK();
}

}  // namespace nrsfm
