#include "solvers/pipeline/result_uncertainty.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "core/math/statistics.h"
#include "solvers/pipeline/drop_unobserved.h"

namespace nrsfm {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

Status ComputeResultUncertainty(const UncertaintyOptions& options,
                                const ReconstructOptions& reconstruct,
                                const Measurements& measurements,
                                const ReconstructResult& result,
                                Uncertainty* uncertainty) {
  if (!result.refine.usable) {
    return Status::Error(
        "uncertainty: the refinement did not give a usable result");
  }
  Unobserved unobserved;
  unobserved.num_bases = result.model.num_bases;
  unobserved.points = result.dropped_points;
  unobserved.frames = result.dropped_frames;
  ProblemOptions problem =
      WithoutUnobserved(reconstruct.problem, measurements, unobserved);
  problem.term_weights = result.priors.term_weights;
  Model model = WithoutUnobserved(result.model, unobserved);
  if (result.repair_strength == 0) {
    // The rigid answer (K = 1, no term) in K bases with weights (1, 0, …):
    // the other bases are not seen, so the covariance is the rigid model's.
    problem.term_weights.clear();
    const Eigen::MatrixXd weights = model.weights.topRows(1);
    const Eigen::MatrixXd basis = model.basis.topRows(3);
    model.num_bases = 1;
    model.weights = weights;
    model.basis = basis;
  }
  const Measurements kept = WithoutUnobserved(measurements, unobserved);
  Uncertainty of_kept;
  NRSFM_RETURN_IF_ERROR(
      ComputeUncertainty(options, problem, kept, model, &of_kept));
  // Back on the full index (the kept covariances moved out, not copied).
  const std::vector<Eigen::Matrix3d> kept_point_covariances =
      std::move(of_kept.points);
  const std::vector<Eigen::Matrix3d> kept_rotation_covariances =
      std::move(of_kept.rotations);
  *uncertainty = std::move(of_kept);
  const int F = measurements.num_frames, M = measurements.num_cameras,
            P = measurements.num_points;
  const Eigen::Matrix3d nan =
      Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
  uncertainty->points.assign(static_cast<size_t>(F) * M * P, nan);
  uncertainty->rotations.assign(static_cast<size_t>(F) * M, nan);
  const std::vector<int> frame_of = KeptIndices(F, unobserved.frames);
  const std::vector<int> point_of = KeptIndices(P, unobserved.points);
  const int kept_points = static_cast<int>(point_of.size());
  for (size_t k = 0; k < frame_of.size(); ++k) {
    for (int c = 0; c < M; ++c) {
      const size_t from = k * M + c,
                   to = static_cast<size_t>(frame_of[k]) * M + c;
      uncertainty->rotations[to] = kept_rotation_covariances[from];
      for (int q = 0; q < kept_points; ++q) {
        uncertainty->points[to * P + point_of[q]] =
            kept_point_covariances[from * kept_points + q];
      }
    }
  }
  return Status::OK();
}

UncertaintySummary SummariseUncertainty(const Uncertainty& uncertainty,
                                        const Model& model) {
  const int num_frames = model.num_frames, num_cameras = model.num_cameras,
            num_points = model.num_points;
  UncertaintySummary summary;
  std::vector<double> extents;
  for (int t = 0; t < num_frames; ++t) {
    const Eigen::Matrix3Xd x = model.ShapeInCamera(t, 0);
    if (!x.allFinite()) {
      // left-out points: the extent of the others
      Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
      bool any = false;
      for (int p = 0; p < num_points; ++p) {
        if (!x.col(p).allFinite()) continue;
        lo = lo.cwiseMin(x.col(p));
        hi = hi.cwiseMax(x.col(p));
        any = true;
      }
      if (any) extents.push_back((hi - lo).maxCoeff());
      continue;
    }
    extents.push_back(
        (x.rowwise().maxCoeff() - x.rowwise().minCoeff()).maxCoeff());
  }
  std::vector<double> stds, depths;
  for (int t = 0; t < num_frames; ++t) {
    double sum = 0;
    int count = 0;
    for (int c = 0; c < num_cameras; ++c) {
      for (int p = 0; p < num_points; ++p) {
        const Eigen::Matrix3d& cov =
            uncertainty.points[(static_cast<size_t>(t) * num_cameras + c) *
                                   num_points +
                               p];
        if (!cov.allFinite()) continue;
        const double std = PointStd(cov);
        stds.push_back(std);
        if (c == 0) depths.push_back(std::sqrt(std::max(0.0, cov(2, 2))));
        summary.max_point_std = std::max(summary.max_point_std, std);
        sum += std * std;
        ++count;
      }
    }
    if (count == 0) continue;
    const double rms = std::sqrt(sum / count);
    if (rms > summary.worst_frame_std) {
      summary.worst_frame_std = rms;
      summary.worst_frame = t;
    }
  }
  summary.median_point_std = UpperMedian(stds, kNaN);
  summary.median_depth_std = UpperMedian(depths, kNaN);
  const double extent = UpperMedian(extents, kNaN);
  summary.relative_depth_std =
      extent > 0 ? summary.median_depth_std / extent : 0.0;
  return summary;
}

}  // namespace nrsfm
