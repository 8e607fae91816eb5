#include "solvers/start/multi_camera_start.h"

#include <glog/logging.h>

#include <vector>

#include "core/math/rotation.h"
#include "solvers/start/pose_fit.h"

namespace nrsfm {
namespace {

constexpr int kPoseSteps = 10;

struct ViewPose {
  bool fitted = false;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  double scale = 1.0;
};

// Step 1 for every view of cameras c ≥ 1 against the shapes of `camera0`.
void FitExtraCameras(const Measurements& centered, const Model& camera0,
                     std::vector<ViewPose>* poses) {
  const int m = centered.num_cameras;
  poses->assign(centered.NumViews(), ViewPose());
  for (int t = 0; t < centered.num_frames; ++t) {
    const Eigen::Matrix3Xd shape = camera0.ShapeInObject(t);
    for (int c = 1; c < m; ++c) {
      const int view = centered.View(t, c);
      const int n = static_cast<int>(centered.visible.row(view).count());
      Eigen::Matrix2Xd observed(2, n);
      Eigen::Matrix3Xd points(3, n);
      for (int p = 0, j = 0; p < centered.num_points; ++p) {
        if (!centered.visible(view, p)) continue;
        observed.col(j) = centered.Observation(t, c, p);
        points.col(j) = shape.col(p);
        ++j;
      }
      ViewPose& pose = (*poses)[view];
      pose.fitted = FitWeakPerspectivePose(observed, points, kPoseSteps,
                                           &pose.rotation, &pose.scale);
    }
  }
}

}  // namespace

Status ExtendToCameras(const Measurements& centered, const Model& camera0,
                       Model* model) {
  CHECK(model != nullptr);
  CHECK_EQ(camera0.num_cameras, 1);
  CHECK_EQ(camera0.num_frames, centered.num_frames);
  CHECK_EQ(camera0.num_points, centered.num_points);
  int views_from_rig = 0;
  const int f = centered.num_frames;
  const int m = centered.num_cameras;
  const int k = camera0.num_bases;

  std::vector<ViewPose> poses;
  FitExtraCameras(centered, camera0, &poses);
  const Model& base = camera0;

  model->Resize(f, m, centered.num_points, k);
  model->weights = base.weights;
  model->basis = base.basis;
  for (int t = 0; t < f; ++t) model->SetRotation(t, 0, base.Rotation(t, 0));
  for (int c = 1; c < m; ++c) {
    Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
    double scale_sum = 0.0;
    int count = 0;
    for (int t = 0; t < f; ++t) {
      const ViewPose& pose = poses[centered.View(t, c)];
      if (!pose.fitted) continue;
      sum += pose.rotation * base.Rotation(t, 0).transpose();
      scale_sum += pose.scale;
      ++count;
    }
    if (count == 0) {
      return Status::Error(
          "multi-camera start: camera " + std::to_string(c) +
          " has no frame with at least 4 visible points spanning 3D; its pose "
          "cannot be estimated");
    }
    const Eigen::Matrix3d rig = NearestRotation(sum);
    const double rig_scale = scale_sum / count;
    model->rig_rotations.col(c - 1) = RotationToAngleAxis(rig);
    model->rig_scales(c - 1) = rig_scale;
    for (int t = 0; t < f; ++t) {
      const int view = centered.View(t, c);
      const ViewPose& pose = poses[view];
      if (pose.fitted) {
        model->SetRotation(t, c, pose.rotation);
        model->scales(view) = pose.scale;
      } else {
        model->SetRotation(t, c, rig * base.Rotation(t, 0));
        model->scales(view) = rig_scale;
        ++views_from_rig;
      }
    }
  }
  VLOG(1) << "multi-camera start: " << m
          << " cameras, views posed from the rig " << views_from_rig;
  return Status::OK();
}

}  // namespace nrsfm
