// How well predicted per-point covariances describe the actual errors
// (docs/uncertainty.md): the calibration and the ranking of an
// uncertainty estimate against ground truth, in the frame e3D compares in.
//
// truth and estimate as for ComputeE3D (core/eval/metrics.h; F frames of
// 3 × P, each centred here), covariances[t · P + p] the 3 × 3 covariance of
// the estimate's centred point (t, p) in the estimate's frame. The e3D
// alignment Y (ComputeE3DDetail) maps the estimate into the truth's frame,
// and each covariance with it (Y Σ Yᵀ). Points whose estimate or covariance
// is not finite are skipped. CHECKs sizes (a programmer error).
#ifndef NRSFM_CORE_EVAL_UNCERTAINTY_METRICS_H_
#define NRSFM_CORE_EVAL_UNCERTAINTY_METRICS_H_

#include <Eigen/Core>
#include <vector>

namespace nrsfm {

// χ²₃ at 0.95: a 3-D Gaussian error lies inside the ellipsoid
// eᵀ Σ⁻¹ e ≤ kChiSquare3At95 with probability 0.95.
inline constexpr double kChiSquare3At95 = 7.814727903251178;

struct UncertaintyCalibration {
  int num_points = 0;  // (t, p) pairs scored
  // Fraction of the true points inside their 95 % ellipsoid (0.95 when the
  // covariances are right).
  double inside_95 = 0.0;
  // Mean Mahalanobis² eᵀ Σ⁻¹ e (3 when right).
  double mean_mahalanobis_squared = 0.0;
  // Spearman rank correlation between each point's predicted
  // sqrt(trace Σ) and its actual 3-D error ||e|| (points averaged over
  // frames first: one value per point p), and the same over every (t, p).
  double spearman_per_point = 0.0;
  double spearman_per_entry = 0.0;
  // Median predicted sqrt(trace Σ) and median actual ||e||, truth units.
  double median_predicted = 0.0, median_actual = 0.0;
};

// With `with_scale` (an answer fixed up to scale: a perspective result) the
// alignment has one global scale c too (ComputeE3DDetail): the estimate
// becomes c Y X̂ and each covariance c² Y Σ Yᵀ.
UncertaintyCalibration ScoreUncertainty(
    const std::vector<Eigen::Matrix3Xd>& truth,
    const std::vector<Eigen::Matrix3Xd>& estimate,
    const std::vector<Eigen::Matrix3d>& covariances, bool with_scale = false);

// Spearman's ρ of two equally long samples (average ranks for ties); 0 for
// fewer than 2 values or a constant sample.
double SpearmanCorrelation(const std::vector<double>& a,
                           const std::vector<double>& b);

}  // namespace nrsfm

#endif  // NRSFM_CORE_EVAL_UNCERTAINTY_METRICS_H_
