#include "solvers/pipeline/perspective.h"

#include <glog/logging.h>

#include <cmath>
#include <string>

#include "core/math/rotation.h"

namespace nrsfm {

Model PerspectiveFromWeak(const Model& weak, const Eigen::Matrix4Xd& intrinsics,
                          bool reflect) {
  CHECK_EQ(intrinsics.cols(), weak.num_cameras);
  Model model = weak;
  model.camera = CameraModel::kPerspective;
  model.intrinsics = intrinsics;
  const Eigen::Matrix3d z = Eigen::Vector3d(1.0, 1.0, -1.0).asDiagonal();
  for (int t = 0; t < weak.num_frames; ++t) {
    for (int c = 0; c < weak.num_cameras; ++c) {
      const int view = weak.View(t, c);
      const Eigen::Vector4d k = intrinsics.col(c);
      const double depth = k(0) / weak.scales(view);
      model.depths(view) = depth;
      model.translations(0, view) =
          (weak.translations(0, view) - k(2)) * depth / k(0);
      model.translations(1, view) =
          (weak.translations(1, view) - k(3)) * depth / k(1);
      model.scales(view) = 1.0;
      if (reflect) model.SetRotation(t, c, z * weak.Rotation(t, c) * z);
    }
  }
  if (reflect) {
    for (int k = 0; k < weak.num_bases; ++k) {
      model.basis.row(3 * k + 2) *= -1.0;
    }
    for (int c = 1; c < weak.num_cameras; ++c) {
      const Eigen::Matrix3d rig =
          AngleAxisToRotation(weak.rig_rotations.col(c - 1));
      model.rig_rotations.col(c - 1) = RotationToAngleAxis(z * rig * z);
    }
  }
  model.rig_scales.setOnes();
  return model;
}

Status RefinePerspective(const ProblemOptions& problem,
                         const SolverOptions& solver,
                         const Measurements& measurements, const Model& weak,
                         Model* model, RefineSummary* summary) {
  if (measurements.intrinsics.cols() != measurements.num_cameras) {
    return Status::Error(
        "the perspective camera needs the intrinsics of every camera (a Kcam "
        "variable in the .mat input, or intrinsics = fx,fy,cx,cy)");
  }
  bool have = false;
  std::string why;
  for (const bool reflect : {false, true}) {
    Model candidate =
        PerspectiveFromWeak(weak, measurements.intrinsics, reflect);
    RefineSummary refined;
    const Status status =
        Refine(problem, solver, measurements, &candidate, &refined);
    if (!status.ok()) return status;
    if (!refined.usable) {
      why = refined.message;
      continue;
    }
    if (!have || refined.final_cost < summary->final_cost) {
      *model = std::move(candidate);
      *summary = refined;
      have = true;
    }
    if (solver.stop_requested && solver.stop_requested()) break;
  }
  if (!have) {
    return Status::Error("the perspective refinement was not usable: " + why);
  }
  return Status::OK();
}

bool SetMeanDepth(double depth, Model* model) {
  CHECK(depth > 0.0);
  for (int t = 0; t < model->num_frames; ++t) {
    if (!model->weights.col(t).allFinite()) continue;
    const Eigen::Matrix3Xd x = model->ShapeInCamera(t, 0);
    double sum = 0.0;
    int n = 0;
    for (int p = 0; p < model->num_points; ++p) {
      if (!x.col(p).allFinite()) continue;
      sum += x(2, p);
      ++n;
    }
    if (n == 0) continue;
    const double mean = sum / n;
    if (!(mean > 0.0)) return false;
    const double factor = depth / mean;
    model->basis *= factor;
    model->translations *= factor;
    model->depths *= factor;
    return true;
  }
  return false;
}

}  // namespace nrsfm
