#include "core/eval/metrics.h"

#include <glog/logging.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

#include "core/math/procrustes.h"
#include "core/math/svd.h"

namespace nrsfm {
namespace {

void CheckSizes(const std::vector<Eigen::Matrix3Xd>& truth,
                const std::vector<Eigen::Matrix3Xd>& estimate) {
  CHECK_GE(truth.size(), 1u);
  CHECK_EQ(truth.size(), estimate.size());
  for (size_t t = 0; t < truth.size(); ++t) {
    CHECK_GE(truth[t].cols(), 1) << "frame " << t;
    CHECK_EQ(truth[t].cols(), truth[0].cols()) << "frame " << t;
    CHECK_EQ(estimate[t].cols(), truth[t].cols()) << "frame " << t;
  }
}

std::vector<Eigen::Matrix3Xd> Centred(
    const std::vector<Eigen::Matrix3Xd>& shapes) {
  std::vector<Eigen::Matrix3Xd> centred;
  centred.reserve(shapes.size());
  for (const Eigen::Matrix3Xd& x : shapes) {
    centred.push_back(x.colwise() - x.rowwise().mean());
  }
  return centred;
}

// Mean over rows of the population std of the rows of the centred truth.
double E3DScale(const std::vector<Eigen::Matrix3Xd>& centred_truth) {
  double sum = 0.0;
  for (const Eigen::Matrix3Xd& x : centred_truth) {
    sum += (x.rowwise().squaredNorm() / static_cast<double>(x.cols()))
               .cwiseSqrt()
               .sum();
  }
  return sum / (3.0 * static_cast<double>(centred_truth.size()));
}

// Centred truth minus the globally aligned, centred estimate.
std::vector<Eigen::Matrix3Xd> AlignedResiduals(
    const std::vector<Eigen::Matrix3Xd>& truth,
    const std::vector<Eigen::Matrix3Xd>& estimate) {
  CheckSizes(truth, estimate);
  std::vector<Eigen::Matrix3Xd> x = Centred(truth);
  const std::vector<Eigen::Matrix3Xd> x_hat = Centred(estimate);
  const Eigen::Matrix3d y = AlignLeastSquaresThenOrthogonal(x, x_hat);
  for (size_t t = 0; t < x.size(); ++t) x[t] -= y * x_hat[t];
  return x;
}

// (1 / FP) Σ_t Σ_p ||r_tp||.
double MeanPointDistance(const std::vector<Eigen::Matrix3Xd>& residuals) {
  double sum = 0.0;
  for (const Eigen::Matrix3Xd& r : residuals) {
    sum += r.colwise().norm().mean();
  }
  return sum / static_cast<double>(residuals.size());
}

// The errors of ComputeE3D, ComputeError3DPercent and ComputeZErrorPercent
// from the aligned residuals (AlignedResiduals) and, for the last two,
// ShapeSize(truth): EvaluateShapes aligns and measures the truth once for
// the three.
double E3DFromResiduals(const std::vector<Eigen::Matrix3Xd>& residuals,
                        const std::vector<Eigen::Matrix3Xd>& truth) {
  return MeanPointDistance(residuals) / E3DScale(Centred(truth));
}

double Error3DPercentFromResiduals(
    const std::vector<Eigen::Matrix3Xd>& residuals, double shape_size) {
  return 100.0 * MeanPointDistance(residuals) / shape_size;
}

double ZErrorPercentFromResiduals(
    const std::vector<Eigen::Matrix3Xd>& residuals, double shape_size) {
  double sum = 0.0;
  for (const Eigen::Matrix3Xd& r : residuals) sum += r.row(2).cwiseAbs().mean();
  return 100.0 * sum / static_cast<double>(residuals.size()) / shape_size;
}

}  // namespace

double ComputeE3D(const std::vector<Eigen::Matrix3Xd>& truth,
                  const std::vector<Eigen::Matrix3Xd>& estimate) {
  return E3DFromResiduals(AlignedResiduals(truth, estimate), truth);
}

double ComputeRankFloorE3D(const std::vector<Eigen::Matrix3Xd>& truth,
                           int num_bases) {
  CHECK(!truth.empty());
  CHECK_GE(num_bases, 1);
  const std::vector<Eigen::Matrix3Xd> centred = Centred(truth);
  const int frames = static_cast<int>(centred.size());
  const int p3 = 3 * static_cast<int>(centred[0].cols());
  Eigen::MatrixXd shapes(frames, p3);
  for (int t = 0; t < frames; ++t) {
    CHECK_EQ(centred[t].cols() * 3, p3);
    shapes.row(t) = Eigen::Map<const Eigen::RowVectorXd>(centred[t].data(), p3);
  }
  const ThinSvd svd = ComputeThinSvd(shapes, SingularVectors::kBoth);
  const int rank = std::min<int>(num_bases, svd.singular_values.size());
  const Eigen::MatrixXd approximation =
      svd.u.leftCols(rank) * svd.singular_values.head(rank).asDiagonal() *
      svd.v.leftCols(rank).transpose();
  std::vector<Eigen::Matrix3Xd> estimate(frames);
  for (int t = 0; t < frames; ++t) {
    const Eigen::RowVectorXd row = approximation.row(t);
    estimate[t] = Eigen::Map<const Eigen::Matrix3Xd>(row.data(), 3, p3 / 3);
  }
  return ComputeE3D(truth, estimate);
}

E3DDetail ComputeE3DDetail(const std::vector<Eigen::Matrix3Xd>& truth,
                           const std::vector<Eigen::Matrix3Xd>& estimate,
                           bool with_scale) {
  CheckSizes(truth, estimate);
  const std::vector<Eigen::Matrix3Xd> x = Centred(truth);
  std::vector<Eigen::Matrix3Xd> aligned = Centred(estimate);
  E3DDetail detail;
  detail.alignment = AlignLeastSquaresThenOrthogonal(x, aligned);
  detail.scale = E3DScale(x);
  double cross = 0.0, norm = 0.0;
  for (std::size_t t = 0; t < x.size(); ++t) {
    aligned[t] = detail.alignment * aligned[t];
    cross += (x[t].array() * aligned[t].array()).sum();
    norm += aligned[t].squaredNorm();
  }
  if (with_scale && norm > 0.0) detail.estimate_scale = cross / norm;
  for (std::size_t t = 0; t < x.size(); ++t) {
    detail.frame_errors.push_back(
        (x[t] - detail.estimate_scale * aligned[t]).colwise().norm().mean() /
        detail.scale);
  }
  return detail;
}

double ComputeScaledE3D(const std::vector<Eigen::Matrix3Xd>& truth,
                        const std::vector<Eigen::Matrix3Xd>& estimate) {
  const E3DDetail detail =
      ComputeE3DDetail(truth, estimate, /*with_scale=*/true);
  double sum = 0.0;
  for (double e : detail.frame_errors) sum += e;
  return sum / static_cast<double>(detail.frame_errors.size());
}

double ComputeFrobeniusZSign(const std::vector<Eigen::Matrix3Xd>& truth,
                             const std::vector<Eigen::Matrix3Xd>& estimate) {
  CheckSizes(truth, estimate);
  const std::vector<Eigen::Matrix3Xd> x = Centred(truth);
  const std::vector<Eigen::Matrix3Xd> x_hat = Centred(estimate);
  double sum = 0.0;
  for (size_t t = 0; t < x.size(); ++t) {
    Eigen::Matrix3Xd flipped = x_hat[t];
    flipped.row(2) *= -1.0;
    const double error =
        std::min((x[t] - x_hat[t]).norm(), (x[t] - flipped).norm());
    sum += error / x[t].norm();
  }
  return sum / static_cast<double>(x.size());
}

namespace {

// The largest distance between two finite columns of `x` (0 with fewer than
// two). Pairs are visited by decreasing distance from the centroid c, and a
// pair (i, j) is skipped when |x_i − c| + |x_j − c|, a bound on its
// distance, cannot exceed the largest distance found so far: the same
// maximum as comparing every pair, in about O(P log P) for compact clouds
// instead of O(P²).
double Diameter(const Eigen::Matrix3Xd& x) {
  std::vector<Eigen::Index> finite;
  finite.reserve(x.cols());
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    if (x.col(i).allFinite()) {
      finite.push_back(i);
      center += x.col(i);
    }
  }
  if (finite.size() < 2) return 0.0;
  center /= static_cast<double>(finite.size());
  std::vector<std::pair<double, Eigen::Index>> by_radius;
  by_radius.reserve(finite.size());
  for (const Eigen::Index i : finite)
    by_radius.emplace_back((x.col(i) - center).norm(), i);
  std::sort(
      by_radius.begin(), by_radius.end(), [](const auto& a, const auto& b) {
        return a.first > b.first || (a.first == b.first && a.second < b.second);
      });
  // The bound is inflated by a relative 1e-9 so that rounding in the radii
  // never skips a pair that is longer than the best one.
  constexpr double kSlack = 1.0 + 1e-9;
  double max_squared = 0.0, best = 0.0;
  const std::size_t n = by_radius.size();
  for (std::size_t a = 0; a + 1 < n; ++a) {
    const double radius = by_radius[a].first;
    if ((radius + by_radius[a + 1].first) * kSlack <= best) break;
    const auto column = x.col(by_radius[a].second);
    for (std::size_t b = a + 1; b < n; ++b) {
      if ((radius + by_radius[b].first) * kSlack <= best) break;
      const double squared =
          (column - x.col(by_radius[b].second)).squaredNorm();
      if (squared > max_squared) {
        max_squared = squared;
        best = std::sqrt(max_squared);
      }
    }
  }
  return std::sqrt(max_squared);
}

}  // namespace

double ShapeSize(const std::vector<Eigen::Matrix3Xd>& truth) {
  CHECK_GE(truth.size(), 1u);
  double sum = 0.0;
  for (const Eigen::Matrix3Xd& x : truth) sum += Diameter(x);
  return sum / static_cast<double>(truth.size());
}

double ComputeError3DPercent(const std::vector<Eigen::Matrix3Xd>& truth,
                             const std::vector<Eigen::Matrix3Xd>& estimate) {
  return Error3DPercentFromResiduals(AlignedResiduals(truth, estimate),
                                     ShapeSize(truth));
}

double ComputeZErrorPercent(const std::vector<Eigen::Matrix3Xd>& truth,
                            const std::vector<Eigen::Matrix3Xd>& estimate) {
  return ZErrorPercentFromResiduals(AlignedResiduals(truth, estimate),
                                    ShapeSize(truth));
}

namespace {

// The user-data checks of EvaluateShapes for one pair of shape sequences;
// `what` names them in the message ("" for the camera frame).
Status CheckShapes(const std::vector<Eigen::Matrix3Xd>& truth,
                   const std::vector<Eigen::Matrix3Xd>& estimate,
                   const std::string& what) {
  std::ostringstream msg;
  if (truth.empty())
    return Status::Error("evaluation: the truth has no frames");
  if (truth.size() != estimate.size()) {
    msg << "evaluation: " << what << "truth has " << truth.size()
        << " frames, estimate has " << estimate.size();
    return Status::Error(msg.str());
  }
  const Eigen::Index num_points = truth[0].cols();
  if (num_points < 1)
    return Status::Error("evaluation: truth frame 0 has no points");
  for (size_t t = 0; t < truth.size(); ++t) {
    if (truth[t].cols() != num_points || estimate[t].cols() != num_points) {
      msg << "evaluation: " << what << "frame " << t << " has "
          << truth[t].cols() << " truth and " << estimate[t].cols()
          << " estimated points, expected " << num_points
          << " (the point count of truth frame 0)";
      return Status::Error(msg.str());
    }
    if (!truth[t].allFinite() || !estimate[t].allFinite()) {
      msg << "evaluation: " << what << "frame " << t << " of the "
          << (truth[t].allFinite() ? "estimate" : "truth")
          << " has a NaN or infinite value";
      return Status::Error(msg.str());
    }
    if ((truth[t].colwise() - truth[t].rowwise().mean()).norm() == 0.0) {
      msg << "evaluation: all points of " << what << "truth frame " << t
          << " coincide; the errors relative to its size are undefined";
      return Status::Error(msg.str());
    }
  }
  return Status::OK();
}

// Whether truth and estimate have the same F and P in every frame (what
// CheckShapes reports otherwise).
bool SameSizes(const GroundTruth& truth, const GroundTruth& estimate) {
  const auto& x = truth.points_in_camera;
  const auto& x_hat = estimate.points_in_camera;
  if (x.empty() || x.size() != x_hat.size()) return false;
  for (std::size_t t = 0; t < x.size(); ++t) {
    if (x[t].cols() != x[0].cols() || x_hat[t].cols() != x[0].cols())
      return false;
  }
  return true;
}

// The frames whose estimated points are all NaN and the points NaN in any
// other frame of the estimate (camera frame, or object frame when it has
// one): what a reconstruction left out.
void FindUnscored(const GroundTruth& estimate, std::vector<int>* frames,
                  std::vector<int>* points) {
  const auto& x_hat = estimate.points_in_camera;
  const int num_points = static_cast<int>(x_hat[0].cols());
  std::vector<bool> point_nan(num_points, false);
  for (std::size_t t = 0; t < x_hat.size(); ++t) {
    const bool object = estimate.HasObjectFrame();
    auto nan = x_hat[t].array().isNaN();
    if (nan.all() &&
        (!object || estimate.points_in_object[t].array().isNaN().all())) {
      frames->push_back(static_cast<int>(t));
      continue;
    }
    for (int p = 0; p < num_points; ++p) {
      point_nan[p] =
          point_nan[p] || nan.col(p).any() ||
          (object && estimate.points_in_object[t].col(p).array().isNaN().any());
    }
  }
  for (int p = 0; p < num_points; ++p) {
    if (point_nan[p]) points->push_back(p);
  }
}

// `shapes` without the frames and points listed (ascending).
GroundTruth Without(const GroundTruth& shapes, const std::vector<int>& frames,
                    const std::vector<int>& points) {
  const int num_points = shapes.NumPoints();
  std::vector<int> kept_points;
  for (int p = 0, i = 0; p < num_points; ++p) {
    if (i < static_cast<int>(points.size()) && points[i] == p) {
      ++i;
    } else {
      kept_points.push_back(p);
    }
  }
  auto columns = [&](const Eigen::Matrix3Xd& x) {
    Eigen::Matrix3Xd out(3, kept_points.size());
    for (std::size_t j = 0; j < kept_points.size(); ++j)
      out.col(j) = x.col(kept_points[j]);
    return out;
  };
  GroundTruth out;
  out.source = shapes.source;
  for (int t = 0, i = 0; t < shapes.NumFrames(); ++t) {
    if (i < static_cast<int>(frames.size()) && frames[i] == t) {
      ++i;
      continue;
    }
    out.points_in_camera.push_back(columns(shapes.points_in_camera[t]));
    if (t < static_cast<int>(shapes.points_in_object.size())) {
      out.points_in_object.push_back(columns(shapes.points_in_object[t]));
    }
    if (t < static_cast<int>(shapes.rotations.size())) {
      out.rotations.push_back(shapes.rotations[t]);
    }
  }
  return out;
}

}  // namespace

const char* EvaluationFrameName(EvaluationFrame frame) {
  return frame == EvaluationFrame::kObject ? "object" : "camera";
}

double ComputeRotationError(const std::vector<Eigen::Matrix3d>& truth,
                            const std::vector<Eigen::Matrix3d>& estimate) {
  CHECK_EQ(truth.size(), estimate.size());
  CHECK(!truth.empty());
  Eigen::Matrix3d cross = Eigen::Matrix3d::Zero();  // Âᵀ A
  for (std::size_t t = 0; t < truth.size(); ++t) {
    cross += estimate[t].topRows<2>().transpose() * truth[t].topRows<2>();
  }
  // argmin_Q ||Â Q − A||_F = argmax tr(Qᵀ Âᵀ A): the orthogonal factor of
  // Âᵀ A.
  const Eigen::Matrix3d q = NearestOrthogonal(cross);
  double sum = 0.0;
  for (std::size_t t = 0; t < truth.size(); ++t) {
    const Eigen::Matrix<double, 2, 3> difference =
        estimate[t].topRows<2>() * q - truth[t].topRows<2>();
    // Spectral norm of a 2 × 3 matrix: sqrt of the largest eigenvalue of the
    // 2 × 2 D Dᵀ.
    const Eigen::Matrix2d gram = difference * difference.transpose();
    const double half_trace = 0.5 * gram.trace();
    const double det = gram.determinant();
    sum += std::sqrt(std::max(
        0.0,
        half_trace + std::sqrt(std::max(0.0, half_trace * half_trace - det))));
  }
  return sum / static_cast<double>(truth.size());
}

Status EvaluateShapes(const GroundTruth& truth, const GroundTruth& estimate,
                      ShapeErrors* errors) {
  CHECK(errors != nullptr);
  *errors = ShapeErrors();
  // What the estimate left out (NaN) is not scored.
  if (SameSizes(truth, estimate)) {
    std::vector<int> frames, points;
    FindUnscored(estimate, &frames, &points);
    if (!frames.empty() || !points.empty()) {
      if (frames.size() == truth.points_in_camera.size() ||
          points.size() == static_cast<std::size_t>(truth.NumPoints())) {
        return Status::Error(
            "evaluation: every frame or every point of the estimate is NaN");
      }
      NRSFM_RETURN_IF_ERROR(EvaluateShapes(Without(truth, frames, points),
                                           Without(estimate, frames, points),
                                           errors));
      errors->num_frames = truth.NumFrames();
      errors->num_points = truth.NumPoints();
      errors->unscored_frames = frames;
      errors->unscored_points = points;
      return Status::OK();
    }
  }
  NRSFM_RETURN_IF_ERROR(
      CheckShapes(truth.points_in_camera, estimate.points_in_camera, ""));
  const std::vector<Eigen::Matrix3Xd>& x = truth.points_in_camera;
  const std::vector<Eigen::Matrix3Xd>& x_hat = estimate.points_in_camera;
  {
    // One alignment and one ShapeSize for the three errors that read them.
    const std::vector<Eigen::Matrix3Xd> residuals = AlignedResiduals(x, x_hat);
    const double shape_size = ShapeSize(x);
    errors->e3d_camera = E3DFromResiduals(residuals, x);
    errors->error3d_pct = Error3DPercentFromResiduals(residuals, shape_size);
    errors->zerror_pct = ZErrorPercentFromResiduals(residuals, shape_size);
  }
  errors->frob_zsign = ComputeFrobeniusZSign(x, x_hat);
  errors->num_frames = static_cast<int>(x.size());
  errors->num_points = static_cast<int>(x[0].cols());
  errors->e3d = errors->e3d_camera;
  errors->e3d_scaled = ComputeScaledE3D(x, x_hat);
  errors->e3d_frame = EvaluationFrame::kCamera;
  if (truth.HasObjectFrame()) {
    if (!estimate.HasObjectFrame()) {
      return Status::Error(
          "evaluation: the truth (" + truth.source +
          ") is scored in the object frame, but the estimate (" +
          estimate.source + ") has no object-frame shapes and rotations");
    }
    NRSFM_RETURN_IF_ERROR(CheckShapes(
        truth.points_in_object, estimate.points_in_object, "object-frame "));
    errors->e3d = ComputeE3D(truth.points_in_object, estimate.points_in_object);
    errors->e3d_scaled =
        ComputeScaledE3D(truth.points_in_object, estimate.points_in_object);
    errors->e3d_frame = EvaluationFrame::kObject;
  }
  if (!truth.rotations.empty() &&
      truth.rotations.size() == estimate.rotations.size()) {
    errors->rotation_error =
        ComputeRotationError(truth.rotations, estimate.rotations);
  }
  return Status::OK();
}

std::vector<std::pair<std::string, double>> MetricList(
    const ShapeErrors& errors) {
  std::vector<std::pair<std::string, double>> list = {
      {"e3d", errors.e3d},
      {"e3d_camera", errors.e3d_camera},
      {"e3d_scaled", errors.e3d_scaled},
      {"frob_zsign", errors.frob_zsign},
      {"error3d_pct", errors.error3d_pct},
      {"zerror_pct", errors.zerror_pct}};
  if (!std::isnan(errors.rotation_error)) {
    list.emplace_back("rotation_error", errors.rotation_error);
  }
  return list;
}

const std::vector<Eigen::Matrix3Xd>& ScoredShapes(const GroundTruth& shapes,
                                                  EvaluationFrame frame) {
  return frame == EvaluationFrame::kObject ? shapes.points_in_object
                                           : shapes.points_in_camera;
}

}  // namespace nrsfm
