#include "track/basis_flow.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace nrsfm {
namespace track {
namespace basis_flow {
namespace {

// A patch that matches its template to this RMS (grey levels) is visible
// whatever its correlation: a weakly textured patch has none to speak of.
constexpr double kFlatPatchRms = 4.0;

}  // namespace

bool Inside(const cv::Size& size, double x, double y) {
  return std::isfinite(x) && std::isfinite(y) && x >= 0.0 && y >= 0.0 &&
         x <= size.width - 1.0 && y <= size.height - 1.0;
}

// A square patch of side `side` centred at (x, y) of `image` (bilinear, the
// border replicated), as float.
cv::Mat Sample(const cv::Mat& image, double x, double y, int side) {
  cv::Mat patch;
  cv::getRectSubPix(image, cv::Size(side, side),
                    cv::Point2f(static_cast<float>(x), static_cast<float>(y)),
                    patch, CV_32F);
  return patch;
}

Match Compare(const cv::Mat& templ, const cv::Mat& patch) {
  const int n = templ.rows * templ.cols;
  const double mean_t = cv::mean(templ)[0];
  const double mean_p = cv::mean(patch)[0];
  double st = 0.0, sp = 0.0, stp = 0.0, sd = 0.0;
  for (int r = 0; r < templ.rows; ++r) {
    const float* t = templ.ptr<float>(r);
    const float* p = patch.ptr<float>(r);
    for (int c = 0; c < templ.cols; ++c) {
      const double a = t[c] - mean_t;
      const double b = p[c] - mean_p;
      st += a * a;
      sp += b * b;
      stp += a * b;
      sd += (t[c] - p[c]) * (t[c] - p[c]);
    }
  }
  Match match;
  match.correlation = st > 0.0 && sp > 0.0 ? stp / std::sqrt(st * sp) : 0.0;
  match.rms = std::sqrt(sd / n);
  return match;
}

bool Visible(const Match& match, const TrackOptions& options) {
  return match.correlation >= options.min_correlation ||
         match.rms <= kFlatPatchRms;
}

std::vector<cv::Mat> TemplateAt(const Pyramid& pyramid, double x, double y,
                                int side) {
  std::vector<cv::Mat> levels;
  for (std::size_t l = 0; l < pyramid.size(); ++l) {
    const double s = std::ldexp(1.0, -static_cast<int>(l));
    levels.push_back(Sample(pyramid[l], x * s, y * s, side));
  }
  return levels;
}

// The least rank r (3 ≤ r ≤ max_rank) whose approximation of the reliable
// tracks `w` (2n × R) explains every one of them: no track's RMS residual
// above twice `noise` (each is a true track; a rank that leaves one out
// would bend it to the others).
int ChooseRank(const Eigen::MatrixXd& w,
               const Eigen::JacobiSVD<Eigen::MatrixXd>& svd, double noise,
               int max_rank) {
  const int top =
      std::min<int>(max_rank, static_cast<int>(svd.singularValues().size()));
  for (int r = 3; r < top; ++r) {
    const Eigen::MatrixXd u = svd.matrixU().leftCols(r);
    const Eigen::MatrixXd residual = w - u * (u.transpose() * w);
    const double worst =
        std::sqrt(residual.colwise().squaredNorm().maxCoeff() / w.rows());
    if (worst <= 2.0 * noise) return r;
  }
  return top;
}

// Adds the priors, each scaled by `scale`, to the normal equations of a step
// from `b`.
void AddPriors(const Eigen::MatrixXd& q,
               const std::vector<PositionPrior>& priors, double scale,
               const Eigen::VectorXd& b, Eigen::MatrixXd* normal,
               Eigen::VectorXd* rhs) {
  for (const PositionPrior& prior : priors) {
    const Eigen::MatrixXd a = q.middleRows(2 * prior.t, 2);
    *normal += scale * a.transpose() * prior.metric * a;
    *rhs += scale * a.transpose() * prior.metric * (prior.position - a * b);
  }
}

// Eq. 9 for one point of a window: the coefficients `b` of its track
// Q̂ b (q: 2n × r, rows x, y of each frame of the window) that fit the
// Lucas–Kanade equations of frames first + 1 … n − 1 relative to its
// template, together with `priors` (its anchor, its own frame-to-frame
// track where that holds, its neighbours' motion). `use[t]` leaves
// occluded frames out of the image equations. Coarse to fine.
void SolveCoefficients(const Eigen::MatrixXd& q,
                       const std::vector<const Pyramid*>& frames, int first,
                       const std::vector<PositionPrior>& priors,
                       const PointState& state, const std::vector<bool>& use,
                       const TrackOptions& options, Eigen::VectorXd* b) {
  const int r = static_cast<int>(q.cols());
  const int n = static_cast<int>(frames.size());
  const int side = options.patch_size;
  const int levels = static_cast<int>(state.templ.size());
  for (int level = levels - 1; level >= 0; --level) {
    const double s = std::ldexp(1.0, -level);
    const cv::Mat& templ = state.templ[level];
    for (int iteration = 0; iteration < options.iterations; ++iteration) {
      Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(r, r);
      Eigen::VectorXd rhs = Eigen::VectorXd::Zero(r);
      double trace_sum = 0.0;
      int used = 0;
      for (int t = first + 1; t < n; ++t) {
        if (!use[t]) continue;
        const Eigen::Matrix<double, 2, Eigen::Dynamic> a =
            q.middleRows(2 * t, 2);
        const Eigen::Vector2d pos = a * *b;
        const cv::Mat patch =
            Sample((*frames[t])[level], pos.x() * s, pos.y() * s, side + 2);
        Eigen::Matrix2d h = Eigen::Matrix2d::Zero();
        Eigen::Vector2d g = Eigen::Vector2d::Zero();
        for (int y = 0; y < side; ++y) {
          const float* up = patch.ptr<float>(y);
          const float* mid = patch.ptr<float>(y + 1);
          const float* down = patch.ptr<float>(y + 2);
          const float* tp = templ.ptr<float>(y);
          for (int x = 0; x < side; ++x) {
            const double gx = 0.5 * (mid[x + 2] - mid[x]) * s;
            const double gy = 0.5 * (down[x + 1] - up[x + 1]) * s;
            const double e = tp[x] - mid[x + 1];
            h(0, 0) += gx * gx;
            h(0, 1) += gx * gy;
            h(1, 1) += gy * gy;
            g(0) += gx * e;
            g(1) += gy * e;
          }
        }
        h(1, 0) = h(0, 1);
        normal += a.transpose() * h * a;
        rhs += a.transpose() * g;
        trace_sum += 0.5 * h.trace();
        ++used;
      }
      // A prior of metric M weighs as M times one frame's image equations.
      const double scale = used > 0 ? trace_sum / used : 1.0;
      AddPriors(q, priors, scale + 1e-9, *b, &normal, &rhs);
      normal.diagonal().array() += 1e-6 * (normal.trace() / r + 1e-9);
      Eigen::VectorXd step = normal.ldlt().solve(rhs);
      if (!step.allFinite()) return;
      // At most a quarter patch of this level per frame and iteration.
      double largest = 0.0;
      for (int t = first; t < n; ++t) {
        largest = std::max(largest, (q.middleRows(2 * t, 2) * step).norm());
      }
      const double limit = 0.25 * side / s;
      if (largest > limit) step *= limit / largest;
      *b += step;
      if (largest * s < 1e-3) break;
    }
  }
}

}  // namespace basis_flow
}  // namespace track
}  // namespace nrsfm
