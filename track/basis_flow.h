// The parts of the rank-constrained tracker (track/tracker.h, kRank) that
// work on one point: its patches and how they match, its template, the rank
// of a window's basis, and eq. 9 of Torresani et al. 2001 (the point's
// coefficients in the basis from all its frames at once). Internal to
// track/.
#ifndef NRSFM_TRACK_BASIS_FLOW_H_
#define NRSFM_TRACK_BASIS_FLOW_H_

#include <Eigen/Core>
#include <Eigen/SVD>
#include <opencv2/core.hpp>
#include <vector>

#include "track/tracks.h"

namespace nrsfm {
namespace track {
namespace basis_flow {

// One frame's pyramid (level 0 = full resolution, each level half the
// previous one).
using Pyramid = std::vector<cv::Mat>;

// Whether (x, y) lies in an image of `size` (pixel centres 0 … size − 1).
bool Inside(const cv::Size& size, double x, double y);

// A square patch of side `side` centred at (x, y) of `image` (bilinear, the
// border replicated), as float.
cv::Mat Sample(const cv::Mat& image, double x, double y, int side);

// How well a patch matches a template: zero-mean normalised
// cross-correlation, and the RMS of the difference (grey levels).
struct Match {
  double correlation = 0.0;
  double rms = 0.0;
};
Match Compare(const cv::Mat& templ, const cv::Mat& patch);

// The patch shows the point: correlation ≥ options.min_correlation, or a
// difference within the image noise (kFlatPatchRms: a weakly textured patch
// has no correlation to speak of).
bool Visible(const Match& match, const TrackOptions& options);

// A point being tracked: its template (the patch at each level, taken at
// its anchor) and whether the anchor position is measured (visible) or
// predicted.
struct PointState {
  std::vector<cv::Mat> templ;  // per level, patch_size²
  bool anchor_measured = true;
};

// The patches of (x, y) at every level of `pyramid`.
std::vector<cv::Mat> TemplateAt(const Pyramid& pyramid, double x, double y,
                                int side);

// The least rank r (3 ≤ r ≤ max_rank) whose approximation of the reliable
// tracks `w` (2n × R; `svd` its thin SVD) explains every one of them: no
// track's RMS residual above twice `noise`.
int ChooseRank(const Eigen::MatrixXd& w,
               const Eigen::JacobiSVD<Eigen::MatrixXd>& svd, double noise,
               int max_rank);

// A position a point's track is drawn to at window frame t: (A_t b − p)ᵀ
// metric (A_t b − p), in units of one frame's Lucas–Kanade equations.
struct PositionPrior {
  int t = 0;
  Eigen::Vector2d position;
  Eigen::Matrix2d metric;
};

// Adds the priors, each scaled by `scale`, to the normal equations of a step
// from `b`.
void AddPriors(const Eigen::MatrixXd& q,
               const std::vector<PositionPrior>& priors, double scale,
               const Eigen::VectorXd& b, Eigen::MatrixXd* normal,
               Eigen::VectorXd* rhs);

// Eq. 9 for one point of a window: the coefficients `b` of its track Q̂ b
// (q: 2n × r, rows x, y of each frame of the window) that fit the
// Lucas–Kanade equations of frames first + 1 … n − 1 relative to its
// template, together with `priors`. `use[t]` leaves occluded frames out of
// the image equations. Gauss–Newton, coarse to fine.
void SolveCoefficients(const Eigen::MatrixXd& q,
                       const std::vector<const Pyramid*>& frames, int first,
                       const std::vector<PositionPrior>& priors,
                       const PointState& state, const std::vector<bool>& use,
                       const TrackOptions& options, Eigen::VectorXd* b);

}  // namespace basis_flow
}  // namespace track
}  // namespace nrsfm

#endif  // NRSFM_TRACK_BASIS_FLOW_H_
