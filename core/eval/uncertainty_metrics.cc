#include "core/eval/uncertainty_metrics.h"

#include <glog/logging.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/eval/metrics.h"
#include "core/math/statistics.h"

namespace nrsfm {
namespace {

std::vector<double> Ranks(const std::vector<double>& values) {
  std::vector<int> order(values.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return values[a] < values[b]; });
  std::vector<double> ranks(values.size());
  for (size_t i = 0; i < order.size();) {
    size_t j = i;
    while (j + 1 < order.size() && values[order[j + 1]] == values[order[i]]) {
      ++j;
    }
    for (size_t k = i; k <= j; ++k) ranks[order[k]] = 0.5 * (i + j);
    i = j + 1;
  }
  return ranks;
}

}  // namespace

double SpearmanCorrelation(const std::vector<double>& a,
                           const std::vector<double>& b) {
  CHECK_EQ(a.size(), b.size());
  if (a.size() < 2) return 0.0;
  const std::vector<double> ra = Ranks(a), rb = Ranks(b);
  const double n = static_cast<double>(a.size());
  const double mean = (n - 1) / 2;
  double ab = 0, aa = 0, bb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    ab += (ra[i] - mean) * (rb[i] - mean);
    aa += (ra[i] - mean) * (ra[i] - mean);
    bb += (rb[i] - mean) * (rb[i] - mean);
  }
  return aa > 0 && bb > 0 ? ab / std::sqrt(aa * bb) : 0.0;
}

UncertaintyCalibration ScoreUncertainty(
    const std::vector<Eigen::Matrix3Xd>& truth,
    const std::vector<Eigen::Matrix3Xd>& estimate,
    const std::vector<Eigen::Matrix3d>& covariances, bool with_scale) {
  CHECK(!truth.empty());
  CHECK_EQ(truth.size(), estimate.size());
  const int F = static_cast<int>(truth.size());
  const int P = static_cast<int>(truth[0].cols());
  CHECK_EQ(covariances.size(), static_cast<size_t>(F) * P);
  const E3DDetail detail = ComputeE3DDetail(truth, estimate, with_scale);
  const Eigen::Matrix3d y = detail.estimate_scale * detail.alignment;
  UncertaintyCalibration score;
  std::vector<double> predicted, actual;
  std::vector<double> point_predicted(P, 0.0), point_actual(P, 0.0);
  std::vector<int> point_count(P, 0);
  int inside = 0;
  double mahalanobis = 0;
  for (int t = 0; t < F; ++t) {
    Eigen::Matrix3Xd x = truth[t], x_hat = estimate[t];
    const Eigen::Vector3d c = x.rowwise().mean(),
                          c_hat = x_hat.rowwise().mean();
    x.colwise() -= c;
    x_hat.colwise() -= c_hat;
    for (int p = 0; p < P; ++p) {
      const Eigen::Matrix3d& cov = covariances[static_cast<size_t>(t) * P + p];
      if (!cov.allFinite() || !x_hat.col(p).allFinite()) continue;
      const Eigen::Vector3d e = x.col(p) - y * x_hat.col(p);
      const Eigen::Matrix3d aligned = y * cov * y.transpose();
      const Eigen::LDLT<Eigen::Matrix3d> ldlt(aligned);
      const double m2 = e.dot(ldlt.solve(e));
      ++score.num_points;
      mahalanobis += m2;
      if (m2 <= kChiSquare3At95) ++inside;
      const double std = std::sqrt(std::max(0.0, aligned.trace()));
      predicted.push_back(std);
      actual.push_back(e.norm());
      point_predicted[p] += std;
      point_actual[p] += e.norm();
      ++point_count[p];
    }
  }
  if (score.num_points == 0) return score;
  score.inside_95 = static_cast<double>(inside) / score.num_points;
  score.mean_mahalanobis_squared = mahalanobis / score.num_points;
  score.spearman_per_entry = SpearmanCorrelation(predicted, actual);
  std::vector<double> per_point_predicted, per_point_actual;
  for (int p = 0; p < P; ++p) {
    if (point_count[p] == 0) continue;
    per_point_predicted.push_back(point_predicted[p] / point_count[p]);
    per_point_actual.push_back(point_actual[p] / point_count[p]);
  }
  score.spearman_per_point =
      SpearmanCorrelation(per_point_predicted, per_point_actual);
  score.median_predicted = UpperMedian(predicted, 0.0);
  score.median_actual = UpperMedian(actual, 0.0);
  return score;
}

}  // namespace nrsfm
