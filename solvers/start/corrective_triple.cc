#include "solvers/start/corrective_triple.h"

#include <ceres/problem.h>
#include <ceres/solver.h>
#include <glog/logging.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/math/parallel_for.h"
#include "core/math/random.h"
#include "core/math/statistics.h"
#include "core/math/svd.h"
#include "core/model/model.h"
#include "problems/orthonormality_error.h"
#include "solvers/refine/solver_options.h"
#include "solvers/start/basis_weight_fit.h"
#include "solvers/start/metric_upgrade.h"
#include "solvers/start/pose_fit.h"

namespace nrsfm {
namespace {

constexpr int kSignRounds = 2;
constexpr double kDamping = 1e-12;  // of the rigid-shape solve
// Two consecutive frames are linked when Σ of the products of their first
// two rotation rows (2 for equal rotations, −2 for a half turn about the
// optical axis) has magnitude ≥ 1.5: rotations within about 40° (about the
// optical axis) to 60° (about an axis in the image plane) of each other with
// one relative sign, and more than 120° apart with the other.
constexpr double kLinkAlignment = 1.5;
// Frames are treated as a time sequence only when at least this fraction of
// consecutive pairs is linked; frames in random order (independent
// rotations) link far less often and keep one sign decision per frame.
constexpr double kMinLinkedFraction = 0.9;

// Levenberg–Marquardt over G (Ceres' defaults, first radius 1e4) with tight
// tolerances.
SolverOptions TripleSolverOptions(int max_iterations) {
  SolverOptions options;
  options.max_iterations = max_iterations;
  options.function_tolerance = 1e-14;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-14;
  options.initial_trust_region_radius = 1e4;
  return options;
}

// The linear solver of a triple solve. `exact`: dense QR of the one
// 2N × 9K Jacobian (accurate to the last bits, for the final solve);
// otherwise its normal equations (half the work, for the screening and the
// polish on a subset).
void SetTripleLinearSolver(bool exact, ceres::Solver::Options* options) {
  if (exact) {
    options->linear_solver_type = ceres::DENSE_QR;
  } else {
    options->linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
    // The gauges (scale, rotation of G) make JᵀJ singular; the damping μ D,
    // μ = 1 / radius, keeps it positive definite only while the radius stays
    // far below 1 / (machine precision), so it is capped there.
    options->max_trust_region_radius = 1e8;
  }
}

// The rows of Q̂ of at most `max_frames` frames spread evenly over the
// sequence (every frame when there are fewer).
Eigen::MatrixXd FrameSubset(const Eigen::MatrixXd& q_hat, int max_frames) {
  const int num_frames = static_cast<int>(q_hat.rows() / 2);
  const int count = std::min(num_frames, max_frames);
  Eigen::MatrixXd rows(2 * count, q_hat.cols());
  for (int i = 0; i < count; ++i) {
    // Frames 0 and F − 1 and evenly between.
    const int t =
        count == 1
            ? 0
            : static_cast<int>((static_cast<long>(i) * (num_frames - 1)) /
                               (count - 1));
    rows.middleRows<2>(2 * i) = q_hat.middleRows<2>(2 * t);
  }
  return rows;
}

// Runs LM on G from its value over the frames of `rows` (TripleSolverOptions,
// SetTripleLinearSolver); the cost per frame (Ceres cost / N), infinity when
// the solve fails or G is not finite.
double SolveTriple(const Eigen::MatrixXd& rows, int max_iterations, bool exact,
                   Eigen::MatrixXd* g) {
  ceres::Problem problem;
  problem.AddResidualBlock(OrthonormalityError::Create(rows), nullptr,
                           g->data());
  ceres::Solver::Summary summary;
  const Status status = SolveCeres(
      TripleSolverOptions(max_iterations),
      [exact](ceres::Solver::Options* options) {
        SetTripleLinearSolver(exact, options);
        return Status::OK();
      },
      &problem, &summary);
  CHECK(status.ok()) << status.message();  // fixed options
  if (!summary.IsSolutionUsable() || !g->allFinite()) {
    return std::numeric_limits<double>::infinity();
  }
  return summary.final_cost / (rows.rows() / 2);
}

// How far the triple's per-frame scale stays from zero: the smallest
// |a₁|² + |a₂|² = c_t² (2 for a unit scaled rotation) over the frames,
// divided by its median.
double ScaleMargin(const Eigen::MatrixXd& q_hat, const Eigen::MatrixXd& g) {
  const Eigen::MatrixXd a = q_hat * g;
  std::vector<double> squared_scales(a.rows() / 2);
  for (std::size_t t = 0; t < squared_scales.size(); ++t) {
    squared_scales[t] = a.middleRows<2>(2 * t).squaredNorm();
  }
  const double smallest =
      *std::min_element(squared_scales.begin(), squared_scales.end());
  const double median = UpperMedian(std::move(squared_scales), 0.0);
  return median > 0.0 ? smallest / median : 0.0;
}

// Least-squares rigid shape given every frame's s_t Π R_t: the basis step of
// the alternation (solvers/start/basis_weight_fit.h) with K = 1.
Eigen::Matrix3Xd FitRigidShape(const Measurements& centered,
                               const std::vector<Eigen::Matrix3d>& rotations,
                               const Eigen::VectorXd& scales) {
  Model rigid;
  rigid.Resize(centered.num_frames, 1, centered.num_points, 1);
  for (int t = 0; t < centered.num_frames; ++t) {
    rigid.SetRotation(t, 0, rotations[t]);
    rigid.weights(0, t) = scales[t];
  }
  FitBasisGivenMotion(centered, kDamping, &rigid);
  return rigid.BasisShape(0);
}

}  // namespace

Status SolveCorrectiveTriple(const Eigen::MatrixXd& q_hat, std::uint64_t seed,
                             int num_threads, Eigen::MatrixX3d* g) {
  CHECK(g != nullptr);
  const int num_frames = static_cast<int>(q_hat.rows() / 2);
  const int n = static_cast<int>(q_hat.cols());
  if (q_hat.rows() % 2 != 0 || num_frames < 2 || n < 3 || n % 3 != 0) {
    std::ostringstream msg;
    msg << "corrective triple: needs a 2F x 3K motion matrix with F >= 2, got "
        << q_hat.rows() << " x " << q_hat.cols();
    return Status::Error(msg.str());
  }
  // Screening: every start a few LM iterations on a subset of the frames.
  const Eigen::MatrixXd screen_rows = FrameSubset(q_hat, kTripleScreenFrames);
  Random random(seed);
  std::vector<Eigen::MatrixXd> starts(kTripleStarts, Eigen::MatrixXd(n, 3));
  for (int start = 0; start < kTripleStarts; ++start) {
    Eigen::MatrixXd& candidate = starts[start];
    MetricUpgrade rigid;
    if (start == 0 && SolveMetricUpgrade(q_hat.leftCols<3>(), &rigid).ok()) {
      // The Tomasi-Kanade triple of the dominant rank-3 part (header).
      candidate.setZero();
      candidate.topRows<3>() = rigid.g;
    } else {
      for (int j = 0; j < 3; ++j) {
        for (int i = 0; i < n; ++i) candidate(i, j) = random.NormalUnpaired();
      }
    }
  }
  std::vector<std::pair<double, int>> screened(kTripleStarts);
  ParallelFor(kTripleStarts, num_threads, /*grain=*/1, [&](int begin, int end) {
    for (int start = begin; start < end; ++start) {
      screened[start] = {SolveTriple(screen_rows, kTripleScreenIterations,
                                     /*exact=*/false, &starts[start]),
                         start};
    }
  });
  // Ties (several starts in one minimum) keep the earlier start.
  std::sort(screened.begin(), screened.end());
  // The best screened starts to convergence on more frames, then the best of
  // them on every frame (a few iterations from there).
  const Eigen::MatrixXd polish_rows = FrameSubset(q_hat, kTriplePolishFrames);
  const int kept = std::min(kTripleKept, kTripleStarts);
  std::vector<double> costs(kept, std::numeric_limits<double>::infinity());
  ParallelFor(kept, num_threads, /*grain=*/1, [&](int begin, int end) {
    for (int i = begin; i < end; ++i) {
      if (std::isfinite(screened[i].first)) {
        costs[i] = SolveTriple(polish_rows, kTripleMaxIterations,
                               /*exact=*/false, &starts[screened[i].second]);
      }
    }
  });
  // The lowest cost wins; costs within kTripleEqualCost of each other are
  // one minimum (noise-free data: every exact triple, cost ~1e-20), and
  // among those the triple whose scale c_t stays furthest from zero does.
  double best_cost = std::numeric_limits<double>::infinity();
  for (double cost : costs) best_cost = std::min(best_cost, cost);
  int best_start = -1;
  double best_margin = -1.0;
  for (int i = 0; i < kept; ++i) {
    const double margin = std::isfinite(costs[i])
                              ? ScaleMargin(q_hat, starts[screened[i].second])
                              : -1.0;
    VLOG(2) << "corrective triple start " << screened[i].second
            << ": screened cost " << screened[i].first
            << ", polished cost per frame " << costs[i] << ", scale margin "
            << margin;
    if (costs[i] <= best_cost + kTripleEqualCost && margin > best_margin) {
      best_margin = margin;
      best_start = screened[i].second;
    }
  }
  if (best_start >= 0) {
    best_cost = SolveTriple(q_hat, kTripleMaxIterations, /*exact=*/true,
                            &starts[best_start]);
    if (!std::isfinite(best_cost)) best_start = -1;
  }
  if (best_start >= 0) *g = starts[best_start];
  if (best_start < 0) {
    return Status::Error(
        "corrective triple: no start converged to a finite solution");
  }
  VLOG(1) << "corrective triple: kept start " << best_start
          << ", cost per frame " << best_cost;
  return Status::OK();
}

Status RotationsFromTriple(const Measurements& centered, int num_bases,
                           std::uint64_t seed, int num_threads,
                           std::vector<Eigen::Matrix3d>* rotations,
                           Eigen::VectorXd* scales,
                           Eigen::Matrix3Xd* rigid_shape,
                           CorrectiveTripleSummary* summary) {
  CHECK(rotations != nullptr && scales != nullptr && rigid_shape != nullptr &&
        summary != nullptr);
  CHECK_EQ(centered.num_cameras, 1);
  const int f = centered.num_frames;
  const int r = 3 * num_bases;
  if (num_bases < 1 || r > 2 * f || r > centered.num_points) {
    std::ostringstream msg;
    msg << "corrective triple: needs 3K <= 2F and 3K <= P; got K = "
        << num_bases << ", F = " << f << ", P = " << centered.num_points;
    return Status::Error(msg.str());
  }
  const ThinSvd svd = ComputeTopSvd(centered.W, r, SingularVectors::kLeft);
  NRSFM_RETURN_IF_ERROR(CheckRotationObservable(svd.singular_values)
                            .WithContext("corrective triple"));
  const Eigen::MatrixXd q_hat =
      svd.u.leftCols(r) * svd.singular_values.head(r).cwiseSqrt().asDiagonal();
  *summary = CorrectiveTripleSummary();
  Eigen::MatrixX3d g;
  NRSFM_RETURN_IF_ERROR(SolveCorrectiveTriple(q_hat, seed, num_threads, &g));

  rotations->assign(f, Eigen::Matrix3d::Identity());
  scales->resize(f);
  for (int t = 0; t < f; ++t) {
    ScaledRotationFromTwoRows(q_hat.middleRows<2>(2 * t) * g, &(*rotations)[t],
                              &(*scales)[t]);
  }
  // Signs (header): link consecutive frames whose rotations are clearly
  // closer with one relative sign than with the other, when the sequence is
  // ordered in time; then one sign per linked segment by the rigid fit.
  const Eigen::Matrix3d half_turn =
      Eigen::Vector3d(-1.0, -1.0, 1.0).asDiagonal();
  // Σ of the products of the first two rows of frames t and t − 1; its
  // magnitude does not change when either frame is turned.
  const auto alignment = [rotations](int t) {
    return ((*rotations)[t].topRows<2>().cwiseProduct(
                (*rotations)[t - 1].topRows<2>()))
        .sum();
  };
  int links = 0;
  for (int t = 1; t < f; ++t) {
    if (std::abs(alignment(t)) >= kLinkAlignment) ++links;
  }
  const bool temporal_signs = f >= 2 && links >= kMinLinkedFraction * (f - 1);
  std::vector<int> segment_start = {0};
  for (int t = 1; t < f; ++t) {
    const double a = alignment(t);  // against the (possibly turned) frame t − 1
    if (temporal_signs && std::abs(a) >= kLinkAlignment) {
      if (a < 0.0) (*rotations)[t] = half_turn * (*rotations)[t];
    } else {
      segment_start.push_back(t);
    }
  }
  segment_start.push_back(f);
  summary->sign_segments = static_cast<int>(segment_start.size()) - 1;
  // A segment whose summed least-squares scale against the rigid shape is
  // negative is seen turned by 180° about the optical axis.
  for (int round = 0; round < kSignRounds; ++round) {
    const Eigen::Matrix3Xd shape = FitRigidShape(centered, *rotations, *scales);
    for (std::size_t s = 0; s + 1 < segment_start.size(); ++s) {
      double scale_sum = 0.0;
      for (int t = segment_start[s]; t < segment_start[s + 1]; ++t) {
        const Eigen::Matrix2Xd projected = (*rotations)[t].topRows<2>() * shape;
        const double denominator = projected.squaredNorm();
        if (!(denominator > 0.0)) continue;
        const double scale =
            (centered.W.middleRows(2 * t, 2).array() * projected.array())
                .sum() /
            denominator;
        scale_sum += scale;
        // The frame's scale against the rigid shape (its sign is the
        // segment's decision below).
        (*scales)[t] = std::abs(scale);
      }
      if (scale_sum < 0.0) {
        for (int t = segment_start[s]; t < segment_start[s + 1]; ++t) {
          (*rotations)[t] = half_turn * (*rotations)[t];
        }
      }
    }
  }
  *rigid_shape = FitRigidShape(centered, *rotations, *scales);
  return Status::OK();
}

}  // namespace nrsfm
