// Reprojection error of one visible observation under a calibrated pinhole
// camera (Model::camera = kPerspective, docs/camera.md), automatically
// differentiated:
//
// clang-format off
//   X = R(ω_tc) · Σ_k l_tk b_p[3k : 3k+3] + (T_tc, t_z,tc)   (camera frame)
//   r = sqrt(w_obs) · ( fx X_x / X_z + cx − u,  fy X_y / X_z + cy − v )
// clang-format on
//
// in pixels (the intrinsics' units). Parameter blocks, in this order:
// rotation ω_tc [3], translation T_tc [2] (the x, y of the camera-frame
// translation), weights l_t [K], basis b_p [3K], depth t_z,tc [1]
// (Model::depths(View(t, c))). A point at or behind the camera (X_z ≤ 0)
// fails the evaluation, so a solver rejects the step that put it there.
#ifndef NRSFM_PROBLEMS_PERSPECTIVE_ERROR_H_
#define NRSFM_PROBLEMS_PERSPECTIVE_ERROR_H_

#include <ceres/dynamic_autodiff_cost_function.h>
#include <ceres/rotation.h>
#include <glog/logging.h>

#include <Eigen/Core>

namespace nrsfm {

class PerspectiveReprojectionError {
 public:
  // `intrinsics` = (fx, fy, cx, cy) of the observation's camera.
  PerspectiveReprojectionError(int num_bases, const Eigen::Vector4d& intrinsics,
                               const Eigen::Vector2d& observation,
                               double sqrt_weight)
      : num_bases_(num_bases),
        intrinsics_{intrinsics(0), intrinsics(1), intrinsics(2), intrinsics(3)},
        observation_{observation.x(), observation.y()},
        sqrt_weight_(sqrt_weight) {
    CHECK_GE(num_bases, 1);
  }

  template <typename T>
  bool operator()(T const* const* parameters, T* residuals) const {
    const T* rotation = parameters[0];
    const T* translation = parameters[1];
    const T* weights = parameters[2];
    const T* basis = parameters[3];
    const T* depth = parameters[4];
    T point[3] = {T(0.0), T(0.0), T(0.0)};
    for (int k = 0; k < num_bases_; ++k) {
      for (int i = 0; i < 3; ++i) point[i] += weights[k] * basis[3 * k + i];
    }
    T x[3];
    ceres::AngleAxisRotatePoint(rotation, point, x);
    x[0] += translation[0];
    x[1] += translation[1];
    x[2] += depth[0];
    if (!(x[2] > T(0.0))) return false;
    residuals[0] = sqrt_weight_ * (intrinsics_[0] * x[0] / x[2] +
                                   intrinsics_[2] - observation_[0]);
    residuals[1] = sqrt_weight_ * (intrinsics_[1] * x[1] / x[2] +
                                   intrinsics_[3] - observation_[1]);
    return true;
  }

  static ceres::CostFunction* Create(int num_bases,
                                     const Eigen::Vector4d& intrinsics,
                                     const Eigen::Vector2d& observation,
                                     double sqrt_weight) {
    // Stride 8: derivatives in passes of 8 parameters.
    auto* cost =
        new ceres::DynamicAutoDiffCostFunction<PerspectiveReprojectionError, 8>(
            new PerspectiveReprojectionError(num_bases, intrinsics, observation,
                                             sqrt_weight));
    cost->AddParameterBlock(3);
    cost->AddParameterBlock(2);
    cost->AddParameterBlock(num_bases);
    cost->AddParameterBlock(3 * num_bases);
    cost->AddParameterBlock(1);
    cost->SetNumResiduals(2);
    return cost;
  }

 private:
  int num_bases_;
  double intrinsics_[4];
  double observation_[2];
  double sqrt_weight_;
};

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_PERSPECTIVE_ERROR_H_
