// The functions of core/eval/metrics.h that read a model and the
// measurements, not the ground truth: the reprojection errors, and a model's
// shapes as the shape metrics take them (ShapesOfModel, CameraFrameShapes).
#include <glog/logging.h>

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <vector>

#include "core/eval/metrics.h"
#include "core/math/parallel_for.h"

namespace nrsfm {
namespace {

// Σ_{visible (t,c,p)} ||w_tcp − projected(t, c)[:, p]||², summed in the order
// t, c, p; with `frame_sums` / `frame_counts` also each frame's part of the
// sum and its number of visible entries (F each). The views' squares are
// formed on up to `num_threads` threads and added in that order on one, so
// the sums are the same bits for any thread count.
template <typename Projection>
double SumSquaredDistances(const Measurements& measurements,
                           const Projection& projected,
                           Eigen::VectorXd* frame_sums,
                           Eigen::VectorXi* frame_counts, int num_threads = 1) {
  const int num_points = measurements.num_points;
  const int num_cameras = measurements.num_cameras;
  // Column (t·M + c): the squares of view (t, c); hidden entries unset.
  Eigen::MatrixXd squares(num_points, measurements.num_frames * num_cameras);
  ParallelFor(static_cast<int>(squares.cols()), num_threads, 1,
              [&](int begin, int end) {
                for (int i = begin; i < end; ++i) {
                  const int t = i / num_cameras, c = i % num_cameras;
                  const Eigen::Matrix2Xd projection = projected(t, c);
                  const int view = measurements.View(t, c);
                  for (int p = 0; p < num_points; ++p) {
                    if (!measurements.visible(view, p)) continue;
                    squares(p, i) =
                        (measurements.Observation(t, c, p) - projection.col(p))
                            .squaredNorm();
                  }
                }
              });
  if (frame_sums != nullptr) frame_sums->setZero(measurements.num_frames);
  if (frame_counts != nullptr) frame_counts->setZero(measurements.num_frames);
  double sum_squared = 0.0;
  for (int t = 0; t < measurements.num_frames; ++t) {
    for (int c = 0; c < num_cameras; ++c) {
      const int view = measurements.View(t, c);
      const double* column = squares.col(t * num_cameras + c).data();
      for (int p = 0; p < num_points; ++p) {
        if (!measurements.visible(view, p)) continue;
        sum_squared += column[p];
        if (frame_sums != nullptr) (*frame_sums)(t) += column[p];
        if (frame_counts != nullptr) ++(*frame_counts)(t);
      }
    }
  }
  return sum_squared;
}

}  // namespace

GroundTruth ShapesOfModel(const Model& model, int camera) {
  CHECK_GE(camera, 0);
  CHECK_LT(camera, model.num_cameras);
  GroundTruth shapes;
  shapes.source = "model";
  for (int t = 0; t < model.num_frames; ++t) {
    shapes.points_in_camera.push_back(model.ShapeInCamera(t, camera));
    shapes.points_in_object.push_back(model.ShapeInObject(t));
    shapes.rotations.push_back(model.Rotation(t, camera));
  }
  return shapes;
}

double ReprojectionRms(const Measurements& measurements, const Model& model,
                       int num_threads) {
  const double sum_squared =
      ReprojectionSquaredError(measurements, model, num_threads);
  const int count = measurements.NumVisible();
  if (count == 0) return std::numeric_limits<double>::quiet_NaN();
  return std::sqrt(sum_squared / count);
}

double ReprojectionSquaredError(const Measurements& measurements,
                                const Model& model, int num_threads) {
  CHECK_EQ(measurements.num_frames, model.num_frames);
  CHECK_EQ(measurements.num_cameras, model.num_cameras);
  CHECK_EQ(measurements.num_points, model.num_points);
  return SumSquaredDistances(
      measurements, [&](int t, int c) { return model.Project(t, c); }, nullptr,
      nullptr, num_threads);
}

FrameReprojectionRms ComputeFrameReprojectionRms(
    const Measurements& measurements, const Eigen::MatrixXd& reprojections) {
  CHECK_EQ(reprojections.rows(), measurements.W.rows());
  CHECK_EQ(reprojections.cols(), measurements.num_points);
  Eigen::VectorXd frame_sums;
  Eigen::VectorXi frame_counts;
  const double total = SumSquaredDistances(
      measurements,
      [&](int t, int c) {
        return reprojections.middleRows<2>(measurements.Row(t, c));
      },
      &frame_sums, &frame_counts);
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  FrameReprojectionRms rms;
  rms.frame_rms = Eigen::VectorXd::Constant(measurements.num_frames, kNaN);
  for (int t = 0; t < measurements.num_frames; ++t) {
    if (frame_counts(t) > 0)
      rms.frame_rms(t) = std::sqrt(frame_sums(t) / frame_counts(t));
  }
  const int count = frame_counts.sum();
  rms.rms = count > 0 ? std::sqrt(total / count) : kNaN;
  return rms;
}

std::vector<Eigen::Matrix3Xd> CameraFrameShapes(const Model& model,
                                                int camera) {
  CHECK_GE(camera, 0);
  CHECK_LT(camera, model.num_cameras);
  std::vector<Eigen::Matrix3Xd> shapes;
  shapes.reserve(model.num_frames);
  for (int t = 0; t < model.num_frames; ++t) {
    shapes.push_back(model.ShapeInCamera(t, camera));
  }
  return shapes;
}

}  // namespace nrsfm
