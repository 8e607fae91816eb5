#include "solvers/start/low_rank_completion.h"

#include <glog/logging.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

#include "core/math/parallel_for.h"
#include "core/math/svd.h"
#include "core/model/option_checker.h"

namespace nrsfm {
namespace {

// Relative residual below which the fit is taken as exact (round-off level).
constexpr double kExactFitRelative = 1e-13;
// Relative decrease of the residual RMS below which the ALS stops
// (dimensionless).
constexpr double kTolerance = 1e-12;
// Tikhonov weight of every normal matrix N, relative to tr(N) / n
// (dimensionless): only keeps a rank-deficient solve finite.
constexpr double kDamping = 1e-12;

// Solves (N + Λ) X = rhs for symmetric positive semi-definite N (n × n),
// Λ = diag(damping · tr(N) / n + ridge on the first `penalised` unknowns,
// damping · tr(N) / n on the others).
Eigen::MatrixXd SolveDamped(Eigen::MatrixXd normal, const Eigen::MatrixXd& rhs,
                            double damping, double ridge, int penalised) {
  const double n = static_cast<double>(normal.rows());
  const double trace = normal.trace();
  normal.diagonal().array() +=
      damping * (trace > 0.0 ? trace / n : 1.0) + 1e-300;
  normal.diagonal().head(penalised).array() += ridge;
  return normal.ldlt().solve(rhs);
}

struct VisibleIndex {
  std::vector<std::vector<int>> points_of_view;  // visible columns per view
  std::vector<std::vector<int>> views_of_point;  // visible views per point
};

VisibleIndex IndexVisible(const VisibilityMask& visible) {
  VisibleIndex index;
  index.points_of_view.resize(visible.rows());
  index.views_of_point.resize(visible.cols());
  for (int p = 0; p < visible.cols(); ++p) {
    for (int v = 0; v < visible.rows(); ++v) {
      if (!visible(v, p)) continue;
      index.points_of_view[v].push_back(p);
      index.views_of_point[p].push_back(v);
    }
  }
  return index;
}

// Step 1: [a_i; t_i] of the two rows of every view given B.
// Views run on up to `num_threads` threads, each on its own.
void SolveRows(const Eigen::MatrixXd& w, const VisibleIndex& index,
               const Eigen::MatrixXd& b, double damping, double ridge,
               int num_threads, Eigen::MatrixXd* a, Eigen::VectorXd* t) {
  const int r = static_cast<int>(b.rows());
  const int views = static_cast<int>(index.points_of_view.size());
  ParallelFor(views, num_threads, /*grain=*/4, [&](int begin, int end) {
    for (int v = begin; v < end; ++v) {
      const std::vector<int>& cols = index.points_of_view[v];
      const int n = static_cast<int>(cols.size());
      Eigen::MatrixXd design(r + 1, n);  // columns [b_p; 1]
      Eigen::MatrixXd data(2, n);
      for (int j = 0; j < n; ++j) {
        design.col(j).head(r) = b.col(cols[j]);
        design(r, j) = 1.0;
        data.col(j) = w.block(2 * v, cols[j], 2, 1);
      }
      const Eigen::MatrixXd normal = design * design.transpose();
      const Eigen::MatrixXd x =
          SolveDamped(normal, design * data.transpose(), damping, ridge, r);
      for (int row = 0; row < 2; ++row) {
        a->row(2 * v + row) = x.col(row).head(r).transpose();
        (*t)(2 * v + row) = x(r, row);
      }
    }
  });
}

// Step 2: b_p of every column given A and t.
// Points run on up to `num_threads` threads, each on its own.
void SolveColumns(const Eigen::MatrixXd& w, const VisibleIndex& index,
                  const Eigen::MatrixXd& a, const Eigen::VectorXd& t,
                  double damping, double ridge, int num_threads,
                  Eigen::MatrixXd* b) {
  const int r = static_cast<int>(a.cols());
  const int points = static_cast<int>(index.views_of_point.size());
  ParallelFor(points, num_threads, /*grain=*/64, [&](int begin, int end) {
    for (int p = begin; p < end; ++p) {
      const std::vector<int>& views = index.views_of_point[p];
      const int n = static_cast<int>(views.size());
      Eigen::MatrixXd design(r, 2 * n);  // columns a_i
      Eigen::VectorXd data(2 * n);
      for (int j = 0; j < n; ++j) {
        for (int row = 0; row < 2; ++row) {
          const int i = 2 * views[j] + row;
          design.col(2 * j + row) = a.row(i).transpose();
          data(2 * j + row) = w(i, p) - t(i);
        }
      }
      b->col(p) = SolveDamped(design * design.transpose(), design * data,
                              damping, ridge, r);
    }
  });
}

// Step 3: centre and orthonormalise the rows of B, keeping A B + t 1ᵀ.
void NormalizeGauge(Eigen::MatrixXd* a, Eigen::VectorXd* t,
                    Eigen::MatrixXd* b) {
  const Eigen::VectorXd mean = b->rowwise().mean();
  b->colwise() -= mean;
  *t += (*a) * mean;
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(b->transpose());
  const Eigen::MatrixXd q =
      qr.householderQ() * Eigen::MatrixXd::Identity(b->cols(), b->rows());
  const Eigen::MatrixXd r_upper =
      qr.matrixQR().topRows(b->rows()).triangularView<Eigen::Upper>();
  *a = (*a) * r_upper.transpose();
  *b = q.transpose();
}

double ResidualRms(const Eigen::MatrixXd& w, const VisibleIndex& index,
                   const Eigen::MatrixXd& a, const Eigen::VectorXd& t,
                   const Eigen::MatrixXd& b) {
  // The squares are summed view by view, point by point; they are formed
  // point by point (W's columns, b's column shared by the views) and kept
  // at their place in that order.
  const int views = static_cast<int>(index.points_of_view.size());
  std::vector<std::size_t> next(views);  // per view: its next entry
  std::size_t count = 0;
  for (int v = 0; v < views; ++v) {
    next[v] = count;
    count += index.points_of_view[v].size();
  }
  std::vector<double> squares(2 * count);
  for (std::size_t p = 0; p < index.views_of_point.size(); ++p) {
    for (const int v : index.views_of_point[p]) {
      double* out = squares.data() + 2 * next[v]++;
      for (int row = 0; row < 2; ++row) {
        const int i = 2 * v + row;
        const double e = w(i, p) - a.row(i).dot(b.col(p)) - t(i);
        out[row] = e * e;
      }
    }
  }
  double sum = 0.0;
  for (const double square : squares) sum += square;
  return count > 0 ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
}

}  // namespace

Status LowRankCompletionOptions::Check() const {
  OptionChecker check("low-rank completion options");
  check.AtLeast("max_iterations", max_iterations, 1);
  check.FiniteAtLeast("ridge_floor", ridge_floor, 0.0);
  return check.status();
}

Status CompleteLowRankAffine(const Measurements& measurements, int rank,
                             const LowRankCompletionOptions& options,
                             LowRankCompletion* completion, int num_threads) {
  CHECK(completion != nullptr);
  LowRankFactors factors;
  NRSFM_RETURN_IF_ERROR(
      FitLowRankAffine(measurements, rank, options, &factors, num_threads));
  CompleteFromFactors(measurements, factors, completion);
  return Status::OK();
}

Status FitLowRankAffine(const Measurements& measurements, int rank,
                        const LowRankCompletionOptions& options,
                        LowRankFactors* factors, int num_threads) {
  CHECK(factors != nullptr);
  NRSFM_RETURN_IF_ERROR(options.Check());
  if (rank < 1) {
    return Status::Error("low-rank completion: rank must be >= 1, got " +
                         std::to_string(rank));
  }
  NRSFM_RETURN_IF_ERROR(measurements.Validate());
  const int r = rank;
  const int num_rows = 2 * measurements.NumViews();
  const int num_points = measurements.num_points;
  const int num_cameras = measurements.num_cameras;
  if (num_points < r + 1 || num_rows < r + 1) {
    std::ostringstream msg;
    msg << "low-rank completion: a rank-" << r + 1
        << " affine fit needs at least " << r + 1 << " points and " << r + 1
        << " rows of W; got P = " << num_points << ", " << num_rows << " rows";
    return Status::Error(msg.str());
  }
  const VisibleIndex index = IndexVisible(measurements.visible);
  for (int v = 0; v < measurements.NumViews(); ++v) {
    const int n = static_cast<int>(index.points_of_view[v].size());
    if (n < r + 1) {
      std::ostringstream msg;
      msg << "low-rank completion: frame " << v / num_cameras;
      if (num_cameras > 1) msg << ", camera " << v % num_cameras;
      msg << " sees " << n << " points; a rank-" << r + 1
          << " affine fit needs at least " << r + 1;
      return Status::Error(msg.str());
    }
  }
  for (int p = 0; p < num_points; ++p) {
    const int n = static_cast<int>(index.views_of_point[p].size());
    if (2 * n < r) {
      std::ostringstream msg;
      msg << "low-rank completion: point " << p << " is seen in " << n
          << " views; a rank-" << r << " fit needs at least " << (r + 1) / 2;
      return Status::Error(msg.str());
    }
  }

  const Eigen::MatrixXd& w = measurements.W;
  // Step 0: mean-filled, row-centred matrix and its top right singular vectors.
  Eigen::MatrixXd filled = Eigen::MatrixXd::Zero(num_rows, num_points);
  for (int v = 0; v < measurements.NumViews(); ++v) {
    const std::vector<int>& cols = index.points_of_view[v];
    for (int row = 0; row < 2; ++row) {
      const int i = 2 * v + row;
      double mean = 0.0;
      for (int p : cols) mean += w(i, p);
      mean /= static_cast<double>(cols.size());
      for (int p : cols) filled(i, p) = w(i, p) - mean;
    }
  }
  const double data_rms =
      std::sqrt(filled.squaredNorm() / (measurements.NumVisible() + 1e-300));
  Eigen::MatrixXd b =
      ComputeTopSvd(filled, r, SingularVectors::kRight).v.transpose();
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(num_rows, r);
  Eigen::VectorXd t = Eigen::VectorXd::Zero(num_rows);
  NormalizeGauge(&a, &t, &b);  // a, t are set by the first row step
  SolveRows(w, index, b, kDamping, 0.0, num_threads, &a, &t);

  // Ridge (see the header): σ̂² per coordinate from the current residual,
  // at least (ridge_floor · data RMS)²; B has orthonormal rows, so an entry
  // of b_p has mean square 1/P and an entry of a_i ||A||² / (rows · r).
  double residual = ResidualRms(w, index, a, t, b);
  int iteration = 0;
  bool converged = residual <= kExactFitRelative * data_rms;
  while (!converged && iteration < options.max_iterations) {
    ++iteration;
    const double floor_rms = options.ridge_floor * data_rms;
    const double noise_variance =
        0.5 * std::max(residual * residual, floor_rms * floor_rms);
    SolveColumns(w, index, a, t, kDamping, noise_variance * num_points,
                 num_threads, &b);
    NormalizeGauge(&a, &t, &b);
    const double a_mean_square = a.squaredNorm() / (num_rows * r);
    SolveRows(w, index, b, kDamping,
              a_mean_square > 0.0 ? noise_variance / a_mean_square : 0.0,
              num_threads, &a, &t);
    const double previous = residual;
    residual = ResidualRms(w, index, a, t, b);
    converged = residual <= kExactFitRelative * data_rms ||
                previous - residual <= kTolerance * previous;
  }
  VLOG(1) << "low-rank completion: rank " << r << " + 1, " << iteration
          << " rounds, residual RMS " << residual
          << (converged ? "" : " (iteration limit)");

  factors->a = std::move(a);
  factors->b = std::move(b);
  factors->t = std::move(t);
  factors->residual_rms = residual;
  factors->iterations = iteration;
  factors->converged = converged;
  return Status::OK();
}

void CompleteFromFactors(const Measurements& measurements,
                         const LowRankFactors& factors,
                         LowRankCompletion* completion) {
  CHECK(completion != nullptr);
  const Eigen::MatrixXd& w = measurements.W;
  const int num_points = measurements.num_points;
  CHECK_EQ(factors.a.rows(), w.rows());
  CHECK_EQ(factors.b.cols(), num_points);
  completion->completed = w;
  completion->translations = factors.t;
  for (int v = 0; v < measurements.NumViews(); ++v) {
    const bool complete = measurements.visible.row(v).count() == num_points;
    for (int row = 0; row < 2; ++row) {
      const int i = 2 * v + row;
      if (complete) {
        completion->translations(i) = w.row(i).mean();
        continue;
      }
      for (int p = 0; p < num_points; ++p) {
        if (!measurements.visible(v, p)) {
          completion->completed(i, p) =
              factors.a.row(i).dot(factors.b.col(p)) + factors.t(i);
        }
      }
    }
  }
  completion->residual_rms = factors.residual_rms;
  completion->iterations = factors.iterations;
  completion->converged = factors.converged;
}

Status LowRankCompletionMemo::Complete(int rank,
                                       const LowRankCompletionOptions& options,
                                       LowRankCompletion* completion) {
  CHECK(completion != nullptr);
  std::lock_guard<std::mutex> lock(mutex_);
  const Entry* found = nullptr;
  for (const Entry& entry : entries_) {
    if (entry.rank == rank &&
        entry.options.max_iterations == options.max_iterations &&
        entry.options.ridge_floor == options.ridge_floor) {
      found = &entry;
      break;
    }
  }
  if (found == nullptr) {
    Entry entry;
    entry.rank = rank;
    entry.options = options;
    entry.status = FitLowRankAffine(measurements_, rank, options,
                                    &entry.factors, num_threads_);
    entries_.push_back(std::move(entry));
    found = &entries_.back();
  }
  NRSFM_RETURN_IF_ERROR(found->status);
  CompleteFromFactors(measurements_, found->factors, completion);
  return Status::OK();
}

}  // namespace nrsfm
