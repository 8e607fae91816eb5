#include "track/tracker.h"

#include <glog/logging.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "track/basis_flow.h"

namespace nrsfm {
namespace track {
namespace {

// The solver's parts (track/basis_flow.h).
using basis_flow::AddPriors;
using basis_flow::ChooseRank;
using basis_flow::Compare;
using basis_flow::Inside;
using basis_flow::Match;
using basis_flow::PointState;
using basis_flow::PositionPrior;
using basis_flow::Pyramid;
using basis_flow::Sample;
using basis_flow::SolveCoefficients;
using basis_flow::TemplateAt;
using basis_flow::Visible;

// The weights of a point's position priors (track/tracker.h, kRank),
// relative to one frame's image equations: its measured anchor holds it
// firmly; its neighbours' motion (and an anchor that is only predicted)
// only breaks the ties the image leaves.
constexpr double kAnchorWeight = 1e3;
constexpr double kNeighbourWeight = 0.05;

std::string QueryName(const Query& query) {
  return "query of point " + std::to_string(query.point);
}

// Lucas–Kanade from frame t to t + 1 of the window for `points`, with the
// forward–backward check: `next` gets the positions, `ok` whether each step
// holds (found both ways, within max_forward_backward_px, in the image).
void LucasKanadeStep(const Pyramid& from, const Pyramid& to,
                     const std::vector<cv::Point2f>& points,
                     const TrackOptions& options, const cv::Size& size,
                     std::vector<cv::Point2f>* next, std::vector<bool>* ok) {
  next->assign(points.size(), cv::Point2f());
  ok->assign(points.size(), false);
  if (points.empty()) return;
  const cv::Size window(options.patch_size, options.patch_size);
  const cv::TermCriteria criteria(
      cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
  std::vector<unsigned char> status, back_status;
  std::vector<float> error;
  std::vector<cv::Point2f> back;
  cv::calcOpticalFlowPyrLK(from[0], to[0], points, *next, status, error, window,
                           options.pyramid_levels, criteria);
  cv::calcOpticalFlowPyrLK(to[0], from[0], *next, back, back_status, error,
                           window, options.pyramid_levels, criteria);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!status[i]) (*next)[i] = points[i];
    const double fb = cv::norm(back[i] - points[i]);
    (*ok)[i] = status[i] && back_status[i] &&
               fb <= options.max_forward_backward_px &&
               Inside(size, (*next)[i].x, (*next)[i].y);
  }
}

// The pixels of the object region in `grey`'s frame: the mask's nonzero
// pixels, else the bounding box of `positions` grown by a quarter of its
// size on each side (at least a patch), else the whole image.
cv::Mat Region(const cv::Size& size, const cv::Mat& mask,
               const std::vector<cv::Point2f>& positions, int patch) {
  if (!mask.empty()) return mask > 0;
  cv::Mat region(size, CV_8U, cv::Scalar(positions.empty() ? 255 : 0));
  if (positions.empty()) return region;
  cv::Rect2f box = cv::boundingRect(positions);
  const float gx = std::max(0.25f * box.width, static_cast<float>(patch));
  const float gy = std::max(0.25f * box.height, static_cast<float>(patch));
  cv::Rect grown(
      cv::Point(static_cast<int>(box.x - gx), static_cast<int>(box.y - gy)),
      cv::Point(static_cast<int>(box.br().x + gx) + 1,
                static_cast<int>(box.br().y + gy) + 1));
  grown &= cv::Rect(cv::Point(0, 0), size);
  region(grown).setTo(255);
  return region;
}

Status TrackPointsOrThrow(FrameSource* frames, FrameSource* mask,
                          const std::vector<Query>& queries,
                          const TrackOptions& options,
                          const TrackProgress& progress, Tracks* tracks) {
  CHECK(frames != nullptr);
  CHECK(tracks != nullptr);
  NRSFM_RETURN_IF_ERROR(options.Check());
  const auto started = std::chrono::steady_clock::now();
  const int num_frames = frames->num_frames();
  const cv::Size size = frames->size();
  if (mask != nullptr) {
    if (mask->frame_numbers() != frames->frame_numbers()) {
      return Status::Error(mask->name() +
                           ": the mask frames are not numbered "
                           "as the frames of " +
                           frames->name());
    }
    if (mask->size() != size) {
      return Status::Error(mask->name() +
                           ": masks of another size than the "
                           "frames of " +
                           frames->name());
    }
  }
  std::map<int, int> index_of;
  for (int i = 0; i < num_frames; ++i) index_of[frames->frame_numbers()[i]] = i;

  Tracks result;
  result.frame_numbers = frames->frame_numbers();
  std::vector<Eigen::Vector2d> start_position;
  for (const Query& query : queries) {
    const auto it = index_of.find(query.frame);
    if (it == index_of.end()) {
      return Status::Error(QueryName(query) + ": frame " +
                           std::to_string(query.frame) + " is not one of " +
                           frames->name() + "'s frames");
    }
    if (!Inside(size, query.x, query.y)) {
      return Status::Error(QueryName(query) + ": (" + std::to_string(query.x) +
                           ", " + std::to_string(query.y) +
                           ") is outside the " + std::to_string(size.width) +
                           " x " + std::to_string(size.height) + " image");
    }
    result.point_ids.push_back(query.point);
    result.start.push_back(it->second);
    start_position.emplace_back(query.x, query.y);
  }

  std::vector<Pyramid> window;    // the window's frames
  std::vector<int> window_index;  // their frame indices
  auto load = [&](int index, Pyramid* pyramid) -> Status {
    cv::Mat grey;
    NRSFM_RETURN_IF_ERROR(frames->Read(index, &grey));
    cv::buildPyramid(grey, *pyramid, options.pyramid_levels);
    return Status::OK();
  };

  if (queries.empty()) {
    // The tracker's own points in the first frame: half corners, half a
    // grid of the object region.
    Pyramid first;
    NRSFM_RETURN_IF_ERROR(load(0, &first));
    cv::Mat region;
    if (mask != nullptr) {
      cv::Mat m;
      NRSFM_RETURN_IF_ERROR(mask->Read(0, &m));
      region = m > 0;
    } else {
      region = cv::Mat(size, CV_8U, cv::Scalar(255));
    }
    const int margin = options.patch_size / 2;
    cv::Mat inner = cv::Mat::zeros(size, CV_8U);
    if (size.width > 2 * margin && size.height > 2 * margin) {
      region(cv::Rect(margin, margin, size.width - 2 * margin,
                      size.height - 2 * margin))
          .copyTo(inner(cv::Rect(margin, margin, size.width - 2 * margin,
                                 size.height - 2 * margin)));
    }
    std::vector<cv::Point2f> corners;
    const int num_corners = (options.num_auto_points + 1) / 2;
    cv::goodFeaturesToTrack(first[0], corners, num_corners, 0.01,
                            options.patch_size / 2.0, inner);
    const int area = cv::countNonZero(inner);
    if (area == 0) {
      return Status::Error(
          (mask != nullptr ? mask->FrameName(0) : frames->FrameName(0)) +
          ": no room for a point in the first frame");
    }
    const int num_grid =
        options.num_auto_points - static_cast<int>(corners.size());
    const double step =
        std::sqrt(static_cast<double>(area) / std::max(num_grid, 1));
    std::vector<cv::Point2f> grid;
    for (double y = margin + 0.5 * step; y < size.height - margin; y += step) {
      for (double x = margin + 0.5 * step; x < size.width - margin; x += step) {
        if (inner.at<unsigned char>(static_cast<int>(y), static_cast<int>(x))) {
          grid.emplace_back(static_cast<float>(x), static_cast<float>(y));
        }
      }
    }
    for (std::size_t i = 0;
         i < grid.size() &&
         corners.size() < static_cast<std::size_t>(options.num_auto_points);
         ++i) {
      corners.push_back(grid[i]);
    }
    for (std::size_t i = 0; i < corners.size(); ++i) {
      result.point_ids.push_back(static_cast<int>(i));
      result.start.push_back(0);
      start_position.emplace_back(corners[i].x, corners[i].y);
    }
  }

  const int num_points = static_cast<int>(result.point_ids.size());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  result.x = Eigen::MatrixXd::Constant(num_frames, num_points, nan);
  result.y = Eigen::MatrixXd::Constant(num_frames, num_points, nan);
  result.visible = Eigen::MatrixXi::Zero(num_frames, num_points);
  for (int i = 0; i < num_points; ++i) {
    result.x(result.start[i], i) = start_position[i].x();
    result.y(result.start[i], i) = start_position[i].y();
    result.visible(result.start[i], i) = 1;
  }
  std::vector<PointState> states(num_points);
  std::vector<bool> has_template(num_points, false);

  int w0 = 0;
  while (true) {
    const int w1 = std::min(w0 + options.window_frames - 1, num_frames - 1);
    const int n = w1 - w0 + 1;
    // Load the window, keeping its first frame from the previous one.
    std::vector<Pyramid> next_window(n);
    for (int t = 0; t < n; ++t) {
      const int index = w0 + t;
      const auto it =
          std::find(window_index.begin(), window_index.end(), index);
      if (it != window_index.end()) {
        next_window[t] = window[it - window_index.begin()];
      } else {
        NRSFM_RETURN_IF_ERROR(load(index, &next_window[t]));
      }
    }
    window = std::move(next_window);
    window_index.clear();
    for (int t = 0; t < n; ++t) window_index.push_back(w0 + t);

    // The points of the window and where each begins in it.
    std::vector<int> active, first;
    for (int i = 0; i < num_points; ++i) {
      if (result.start[i] > w1) continue;  // begins in a later window
      active.push_back(i);
      first.push_back(std::max(result.start[i], w0) - w0);
    }
    // Templates of the points that begin here, and re-anchoring of those
    // that go on from the previous window where they are visible.
    for (std::size_t k = 0; k < active.size(); ++k) {
      const int i = active[k];
      const int f = first[k];
      const bool seen = result.visible(w0 + f, i) != 0;
      if (!has_template[i] || seen) {
        states[i].templ = TemplateAt(window[f], result.x(w0 + f, i),
                                     result.y(w0 + f, i), options.patch_size);
        has_template[i] = true;
      }
      states[i].anchor_measured = seen;
    }

    // Lucas–Kanade through the window: the query points, then (kRank) the
    // support points, corners of the object region in the first frame.
    std::vector<cv::Point2f> support;
    if (options.method == TrackMethod::kRank) {
      std::vector<cv::Point2f> known;
      for (std::size_t k = 0; k < active.size(); ++k) {
        const int t = w0 + first[k];
        known.emplace_back(static_cast<float>(result.x(t, active[k])),
                           static_cast<float>(result.y(t, active[k])));
      }
      cv::Mat mask_image;
      if (mask != nullptr) {
        NRSFM_RETURN_IF_ERROR(mask->Read(w0, &mask_image));
      }
      const cv::Mat region =
          Region(size, mask_image, known, options.patch_size);
      cv::goodFeaturesToTrack(window[0][0], support, options.num_support_points,
                              0.01, options.patch_size / 4.0, region);
    }
    const int num_active = static_cast<int>(active.size());
    const int num_lk = num_active + static_cast<int>(support.size());
    // lk[t][j]: position at window frame t; lk_ok[t][j]: the chain from the
    // point's first frame to t holds.
    std::vector<std::vector<cv::Point2f>> lk(n,
                                             std::vector<cv::Point2f>(num_lk));
    std::vector<std::vector<bool>> lk_ok(n, std::vector<bool>(num_lk, false));
    std::vector<int> lk_first(num_lk, 0);
    for (int k = 0; k < num_active; ++k) {
      lk_first[k] = first[k];
      lk[first[k]][k] =
          cv::Point2f(static_cast<float>(result.x(w0 + first[k], active[k])),
                      static_cast<float>(result.y(w0 + first[k], active[k])));
      lk_ok[first[k]][k] = true;
    }
    for (std::size_t j = 0; j < support.size(); ++j) {
      lk[0][num_active + j] = support[j];
      lk_ok[0][num_active + j] = true;
    }
    std::vector<std::vector<bool>> step_ok(n, std::vector<bool>(num_lk, false));
    for (int t = 0; t + 1 < n; ++t) {
      std::vector<cv::Point2f> from;
      std::vector<int> which;
      for (int j = 0; j < num_lk; ++j) {
        if (lk_first[j] <= t) {
          from.push_back(lk[t][j]);
          which.push_back(j);
        }
      }
      std::vector<cv::Point2f> to;
      std::vector<bool> ok;
      LucasKanadeStep(window[t], window[t + 1], from, options, size, &to, &ok);
      for (std::size_t m = 0; m < which.size(); ++m) {
        const int j = which[m];
        lk[t + 1][j] = to[m];
        step_ok[t + 1][j] = ok[m];
        lk_ok[t + 1][j] = ok[m] && lk_ok[t][j];
      }
    }

    bool solved = false;
    if (options.method == TrackMethod::kRank) {
      // The reliable tracks of the whole window.
      std::vector<int> reliable;
      for (int j = 0; j < num_lk; ++j) {
        if (lk_first[j] == 0 && lk_ok[n - 1][j]) reliable.push_back(j);
      }
      if (static_cast<int>(reliable.size()) > 3) {
        Eigen::MatrixXd w(2 * n, reliable.size());
        for (std::size_t m = 0; m < reliable.size(); ++m) {
          for (int t = 0; t < n; ++t) {
            w(2 * t, m) = lk[t][reliable[m]].x;
            w(2 * t + 1, m) = lk[t][reliable[m]].y;
          }
        }
        Eigen::JacobiSVD<Eigen::MatrixXd> svd(
            w, Eigen::ComputeThinU | Eigen::ComputeThinV);
        const int top = std::min<int>(options.max_rank,
                                      static_cast<int>(reliable.size()) - 1);
        const int r =
            options.rank > 0
                ? std::min(options.rank,
                           static_cast<int>(svd.singularValues().size()))
                : ChooseRank(w, svd, options.rank_noise_px, std::max(top, 3));
        const Eigen::MatrixXd q = svd.matrixU().leftCols(r);
        std::vector<const Pyramid*> frame_ptrs;
        for (const Pyramid& p : window) frame_ptrs.push_back(&p);
        cv::parallel_for_(
            cv::Range(0, num_active), [&](const cv::Range& range) {
              for (int k = range.start; k < range.end; ++k) {
                const int i = active[k];
                const int f = first[k];
                const Eigen::Vector2d anchor(result.x(w0 + f, i),
                                             result.y(w0 + f, i));
                // The reliable points by distance at the point's first frame.
                std::vector<std::pair<double, int>> near;
                for (std::size_t m = 0; m < reliable.size(); ++m) {
                  if (reliable[m] == k) continue;
                  const cv::Point2f p = lk[f][reliable[m]];
                  near.emplace_back(
                      std::hypot(p.x - anchor.x(), p.y - anchor.y()), m);
                }
                std::sort(near.begin(), near.end());
                const std::size_t count = std::min<std::size_t>(8, near.size());
                // The priors: the anchor (firm when measured), the point's own
                // Lucas–Kanade track while it holds (with the metric of its
                // template's second-moment matrix: along an edge only the
                // normal counts), and the mean motion of the 8 nearest
                // reliable points (weak).
                std::vector<PositionPrior> priors;
                const Eigen::Matrix2d isotropic = Eigen::Matrix2d::Identity();
                priors.push_back(
                    {f, anchor,
                     (states[i].anchor_measured ? kAnchorWeight
                                                : kNeighbourWeight) *
                         isotropic});
                Eigen::Matrix2d structure = Eigen::Matrix2d::Zero();
                {
                  const cv::Mat& t0 = states[i].templ[0];
                  cv::Mat gx, gy;
                  cv::Sobel(t0, gx, CV_32F, 1, 0, 3, 1.0 / 8);
                  cv::Sobel(t0, gy, CV_32F, 0, 1, 3, 1.0 / 8);
                  structure(0, 0) = gx.dot(gx);
                  structure(0, 1) = structure(1, 0) = gx.dot(gy);
                  structure(1, 1) = gy.dot(gy);
                  structure /= 0.5 * structure.trace() + 1e-12;
                }
                for (int t = f + 1; t < n && lk_ok[t][k]; ++t) {
                  priors.push_back(
                      {t, Eigen::Vector2d(lk[t][k].x, lk[t][k].y), structure});
                }
                for (int t = f + 1; t < n && count > 0; ++t) {
                  Eigen::Vector2d motion = Eigen::Vector2d::Zero();
                  for (std::size_t m = 0; m < count; ++m) {
                    const int j = reliable[near[m].second];
                    motion += Eigen::Vector2d(lk[t][j].x - lk[f][j].x,
                                              lk[t][j].y - lk[f][j].y);
                  }
                  priors.push_back({t, anchor + motion / count,
                                    kNeighbourWeight * isotropic});
                }
                Eigen::MatrixXd normal = 1e-9 * Eigen::MatrixXd::Identity(r, r);
                Eigen::VectorXd rhs = Eigen::VectorXd::Zero(r);
                AddPriors(q, priors, 1.0, Eigen::VectorXd::Zero(r), &normal,
                          &rhs);
                Eigen::VectorXd b = normal.ldlt().solve(rhs);
                // Eq. 9 coarse to fine with every frame; then again without the
                // frames that do not match the template (occluded).
                std::vector<bool> use(n, true);
                SolveCoefficients(q, frame_ptrs, f, priors, states[i], use,
                                  options, &b);
                std::vector<Match> match(n);
                bool changed = false;
                for (int t = f + 1; t < n; ++t) {
                  const Eigen::Vector2d pos = q.middleRows(2 * t, 2) * b;
                  match[t] = Compare(states[i].templ[0],
                                     Sample(window[t][0], pos.x(), pos.y(),
                                            options.patch_size));
                  use[t] = Visible(match[t], options) &&
                           Inside(size, pos.x(), pos.y());
                  changed = changed || !use[t];
                }
                if (changed) {
                  SolveCoefficients(q, frame_ptrs, f, priors, states[i], use,
                                    options, &b);
                }
                for (int t = f + 1; t < n; ++t) {
                  const Eigen::Vector2d pos = q.middleRows(2 * t, 2) * b;
                  const Match m = Compare(states[i].templ[0],
                                          Sample(window[t][0], pos.x(), pos.y(),
                                                 options.patch_size));
                  result.x(w0 + t, i) = pos.x();
                  result.y(w0 + t, i) = pos.y();
                  // Visible where the patch matches the template, or where
                  // Lucas–Kanade's own step holds and agrees with the track.
                  const bool step_agrees =
                      step_ok[t][k] &&
                      std::hypot(lk[t][k].x - pos.x(), lk[t][k].y - pos.y()) <=
                          2.0 * options.max_forward_backward_px;
                  result.visible(w0 + t, i) =
                      (Visible(m, options) || step_agrees) &&
                      Inside(size, pos.x(), pos.y());
                }
              }
            });
        result.window_start.push_back(w0);
        result.window_rank.push_back(r);
        solved = true;
      } else {
        ++result.windows_without_basis;
      }
    }
    if (!solved) {
      for (int k = 0; k < num_active; ++k) {
        const int i = active[k];
        for (int t = first[k] + 1; t < n; ++t) {
          result.x(w0 + t, i) = lk[t][k].x;
          result.y(w0 + t, i) = lk[t][k].y;
          result.visible(w0 + t, i) = step_ok[t][k];
        }
      }
    }
    if (progress) progress(w1 + 1, num_frames);
    if (w1 == num_frames - 1) break;
    w0 = w1;
  }
  result.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started)
          .count();
  *tracks = std::move(result);
  return Status::OK();
}

}  // namespace

Status TrackPoints(FrameSource* frames, FrameSource* mask,
                   const std::vector<Query>& queries,
                   const TrackOptions& options, const TrackProgress& progress,
                   Tracks* tracks) {
  // OpenCV reports its failures as exceptions; none leaves the library.
  try {
    return TrackPointsOrThrow(frames, mask, queries, options, progress, tracks);
  } catch (const cv::Exception& e) {
    return Status::Error(frames->name() + ": OpenCV failed: " + e.msg);
  }
}

}  // namespace track
}  // namespace nrsfm
