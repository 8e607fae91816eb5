#include "core/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <glog/logging.h>

#include "core/procrustes.h"

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

}  // namespace

double ComputeE3D(const std::vector<Eigen::Matrix3Xd>& truth,
                  const std::vector<Eigen::Matrix3Xd>& estimate) {
  return MeanPointDistance(AlignedResiduals(truth, estimate)) /
         E3DScale(Centred(truth));
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

double ShapeSize(const std::vector<Eigen::Matrix3Xd>& truth) {
  CHECK_GE(truth.size(), 1u);
  double sum = 0.0;
  for (const Eigen::Matrix3Xd& x : truth) {
    double max_squared = 0.0;
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      for (Eigen::Index j = i + 1; j < x.cols(); ++j) {
        max_squared =
            std::max(max_squared, (x.col(i) - x.col(j)).squaredNorm());
      }
    }
    sum += std::sqrt(max_squared);
  }
  return sum / static_cast<double>(truth.size());
}

double ComputeError3DPercent(const std::vector<Eigen::Matrix3Xd>& truth,
                             const std::vector<Eigen::Matrix3Xd>& estimate) {
  return 100.0 * MeanPointDistance(AlignedResiduals(truth, estimate)) /
         ShapeSize(truth);
}

double ComputeZErrorPercent(const std::vector<Eigen::Matrix3Xd>& truth,
                            const std::vector<Eigen::Matrix3Xd>& estimate) {
  const std::vector<Eigen::Matrix3Xd> residuals =
      AlignedResiduals(truth, estimate);
  double sum = 0.0;
  for (const Eigen::Matrix3Xd& r : residuals) sum += r.row(2).cwiseAbs().mean();
  return 100.0 * sum / static_cast<double>(residuals.size()) / ShapeSize(truth);
}

Status EvaluateShapes(const std::vector<Eigen::Matrix3Xd>& truth,
                      const std::vector<Eigen::Matrix3Xd>& estimate,
                      ShapeErrors* errors) {
  CHECK(errors != nullptr);
  std::ostringstream msg;
  if (truth.empty())
    return Status::Error("evaluation: the truth has no frames");
  if (truth.size() != estimate.size()) {
    msg << "evaluation: truth has " << truth.size() << " frames, estimate has "
        << estimate.size();
    return Status::Error(msg.str());
  }
  const Eigen::Index num_points = truth[0].cols();
  if (num_points < 1)
    return Status::Error("evaluation: truth frame 0 has no points");
  for (size_t t = 0; t < truth.size(); ++t) {
    if (truth[t].cols() != num_points || estimate[t].cols() != num_points) {
      msg << "evaluation: frame " << t << " has " << truth[t].cols()
          << " truth and " << estimate[t].cols()
          << " estimated points, expected " << num_points
          << " (the point count of truth frame 0)";
      return Status::Error(msg.str());
    }
    if (!truth[t].allFinite() || !estimate[t].allFinite()) {
      msg << "evaluation: frame " << t << " of the "
          << (truth[t].allFinite() ? "estimate" : "truth")
          << " has a NaN or infinite value";
      return Status::Error(msg.str());
    }
    if ((truth[t].colwise() - truth[t].rowwise().mean()).norm() == 0.0) {
      msg << "evaluation: all points of truth frame " << t
          << " coincide; the errors relative to its size are undefined";
      return Status::Error(msg.str());
    }
  }
  errors->e3d = ComputeE3D(truth, estimate);
  errors->frob_zsign = ComputeFrobeniusZSign(truth, estimate);
  errors->error3d_pct = ComputeError3DPercent(truth, estimate);
  errors->zerror_pct = ComputeZErrorPercent(truth, estimate);
  errors->num_frames = static_cast<int>(truth.size());
  errors->num_points = static_cast<int>(num_points);
  return Status::OK();
}

double ReprojectionRms(const Measurements& measurements, const Model& model) {
  CHECK_EQ(measurements.num_frames, model.num_frames);
  CHECK_EQ(measurements.num_cameras, model.num_cameras);
  CHECK_EQ(measurements.num_points, model.num_points);
  double sum_squared = 0.0;
  int count = 0;
  for (int t = 0; t < measurements.num_frames; ++t) {
    for (int c = 0; c < measurements.num_cameras; ++c) {
      const Eigen::Matrix2Xd projected = model.Project(t, c);
      const int view = measurements.View(t, c);
      for (int p = 0; p < measurements.num_points; ++p) {
        if (!measurements.visible(view, p)) continue;
        sum_squared += (measurements.Observation(t, c, p) - projected.col(p))
                           .squaredNorm();
        ++count;
      }
    }
  }
  if (count == 0) return std::numeric_limits<double>::quiet_NaN();
  return std::sqrt(sum_squared / count);
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
