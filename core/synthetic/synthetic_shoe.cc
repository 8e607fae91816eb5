#include <glog/logging.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/model/option_checker.h"
#include "core/synthetic/shoe_geometry.h"
#include "core/synthetic/synthetic.h"
#include "core/synthetic/synthetic_common.h"

namespace nrsfm {

using synthetic::AxisRotation;
using synthetic::CentreBasis;
using synthetic::FillMeasurements;
using synthetic::kDegToRad;
using synthetic::kGeometryStream;
using synthetic::kMotionStream;
using synthetic::kShoeSoleY;
using synthetic::RandomCurve;
using synthetic::ShoeParameters;
using synthetic::ShoeSurface;
using synthetic::SmoothCurve;
using synthetic::SmoothStep;
using synthetic::Tau;

namespace {
constexpr double kRigScale = 0.9;  // s_t1 / s_t0
}  // namespace

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
  const Eigen::Vector2d ball(0.15, kShoeSoleY);
  Eigen::Matrix3Xd toe(3, num_points), flex(3, num_points),
      squash(3, num_points);
  for (int p = 0; p < num_points; ++p) {
    const double x = rest(0, p), y = rest(1, p), z = rest(2, p);
    const double height = y - kShoeSoleY;
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
