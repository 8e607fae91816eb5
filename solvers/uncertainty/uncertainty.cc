#include "solvers/uncertainty/uncertainty.h"

#include <ceres/crs_matrix.h>
#include <ceres/problem.h>
#include <glog/logging.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/math/parallel_for.h"
#include "problems/extra_terms.h"
#include "problems/problem_builder.h"
#include "solvers/uncertainty/selected_inverse.h"

namespace nrsfm {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Ldlt = Eigen::SimplicialLDLT<SparseMatrix>;

constexpr int kFrames = 0;  // the side of ω, T, l, s and every shared block
constexpr int kPoints = 1;  // the side of the b_p

// Where one parameter block's tangent coordinates went: their side and their
// index on it, -1 for a coordinate held for the gauge (zero covariance).
struct Columns {
  int side = kFrames;
  std::vector<int> index;
};

// A pivot of the LDLᵀ or LLᵀ factor below this fraction of the largest
// diagonal entry of the matrix counts as zero: a direction the data do not
// determine.
constexpr double kSingularPivot = 1e-13;

// Runs body(first, count) over [0, n) in blocks of kColumnBlock columns,
// block b on thread b mod threads: the blocks, and so the bits, do not
// depend on the thread count.
constexpr int kColumnBlock = 64;
void ForColumnBlocks(int n, int threads,
                     const std::function<void(int, int)>& body) {
  const int blocks = (n + kColumnBlock - 1) / kColumnBlock;
  const int pieces = std::max(1, std::min(threads, blocks));
  ParallelForWorker(pieces, pieces, 1, [&](int begin, int end, int) {
    for (int piece = begin; piece < end; ++piece) {
      for (int b = piece; b < blocks; b += pieces) {
        const int first = b * kColumnBlock;
        body(first, std::min(kColumnBlock, n - first));
      }
    }
  });
}

std::string Count(int n, const char* what) {
  return std::to_string(n) + " " + what;
}

}  // namespace

Status UncertaintyOptions::Check() const {
  if (!(noise_std >= 0.0) || !std::isfinite(noise_std)) {
    return Status::Error("noise_std must be a finite value >= 0, got " +
                         std::to_string(noise_std));
  }
  if (num_threads < 1) {
    return Status::Error("num_threads must be >= 1, got " +
                         std::to_string(num_threads));
  }
  if (max_dense_parameters < 1) {
    return Status::Error("max_dense_parameters must be >= 1, got " +
                         std::to_string(max_dense_parameters));
  }
  if (!(max_bytes >= 1.0)) {
    return Status::Error("max_bytes must be >= 1, got " +
                         std::to_string(max_bytes));
  }
  return Status::OK();
}

double PointStd(const Eigen::Matrix3d& covariance) {
  return std::sqrt(std::max(0.0, covariance.trace()));
}

Status ComputeUncertainty(const UncertaintyOptions& options,
                          const ProblemOptions& problem,
                          const Measurements& measurements, const Model& model,
                          Uncertainty* uncertainty) {
  const auto start_time = std::chrono::steady_clock::now();
  NRSFM_RETURN_IF_ERROR(options.Check().WithContext("uncertainty"));
  NRSFM_RETURN_IF_ERROR(model.Validate().WithContext("uncertainty"));
  Model values = model;  // the builder's blocks; nothing is solved
  ProblemBuilder builder(&measurements, &values);
  NRSFM_RETURN_IF_ERROR(builder.AddReprojectionTerms(problem));
  NRSFM_RETURN_IF_ERROR(AddExtraTerms(problem, &builder));
  ceres::Problem* ceres_problem = builder.problem();
  const int F = model.num_frames, M = model.num_cameras, P = model.num_points,
            K = model.num_bases;

  // Every block must be determined by some residual.
  for (int p = 0; p < P; ++p) {
    if (!ceres_problem->HasParameterBlock(builder.BasisBlock(p))) {
      return Status::Error("uncertainty: point " + std::to_string(p) +
                           " has no observation (leave it out first)");
    }
  }
  for (int t = 0; t < F; ++t) {
    if (!ceres_problem->HasParameterBlock(builder.WeightsBlock(t))) {
      return Status::Error("uncertainty: frame " + std::to_string(t) +
                           " has no observation (leave it out first)");
    }
  }

  // The gauge (header): held coordinates, when the gauge is one (a kind of
  // block held by the options already fixes it).
  const bool rotation_gauge =
      !problem.constant_rotations && !problem.constant_basis;
  const bool mixing_gauge =
      !problem.constant_weights && !problem.constant_basis;
  const bool shift_gauge =
      !problem.constant_translations && !problem.constant_basis;
  std::map<const double*, bool> held;
  if (rotation_gauge) {
    for (int v = 0; v < F * M; ++v) {
      double* block = builder.RotationBlock(v / M, v % M);
      if (ceres_problem->HasParameterBlock(block)) {
        held[block] = true;
        break;
      }
    }
  }
  if (mixing_gauge) {
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(model.weights);
    for (int k = 0; k < K; ++k) {
      held[builder.WeightsBlock(qr.colsPermutation().indices()(k))] = true;
    }
  }
  if (shift_gauge) {
    const Eigen::VectorXi seen = measurements.VisiblePerPoint();
    int most = 0;
    seen.maxCoeff(&most);
    held[builder.BasisBlock(most)] = true;
  }

  // Columns: the frames' side (every block but the points), then the points'.
  std::vector<double*> blocks;
  std::vector<int> block_side;
  // In an order that does not depend on where the blocks are in memory
  // (NonPointBlocks' does), so that the factor's ordering and every sum are
  // the same from run to run.
  for (const std::vector<double*>& group : builder.NonPointBlockGroups()) {
    for (double* block : group) {
      if (ceres_problem->IsParameterBlockConstant(block)) continue;
      blocks.push_back(block);
      block_side.push_back(kFrames);
    }
  }
  for (double* block : builder.PointBlocks()) {
    if (ceres_problem->IsParameterBlockConstant(block)) continue;
    blocks.push_back(block);
    block_side.push_back(kPoints);
  }
  std::map<const double*, Columns> columns_of;
  std::vector<std::pair<int, int>> column_map;  // Jacobian column → (side, i)
  int side_size[2] = {0, 0};
  int gauge_size = 0;
  for (size_t b = 0; b < blocks.size(); ++b) {
    const int size = ceres_problem->ParameterBlockTangentSize(blocks[b]);
    const bool is_held = held.count(blocks[b]) > 0;
    Columns& columns = columns_of[blocks[b]];
    columns.side = block_side[b];
    for (int i = 0; i < size; ++i) {
      const int index = is_held ? -1 : side_size[block_side[b]]++;
      columns.index.push_back(index);
      column_map.emplace_back(block_side[b], index);
    }
    if (is_held) gauge_size += size;
  }
  const int num_parameters = side_size[0] + side_size[1];
  // Blocks the problem holds constant (the perspective camera's gauge:
  // problems/problem_builder.h) have no column: zero perturbation.
  const auto add_constant = [&](double* block, int side) {
    if (!ceres_problem->HasParameterBlock(block) ||
        !ceres_problem->IsParameterBlockConstant(block)) {
      return;
    }
    Columns& columns = columns_of[block];
    columns.side = side;
    columns.index.assign(ceres_problem->ParameterBlockSize(block), -1);
  };
  for (double* block : builder.NonPointBlocks()) add_constant(block, kFrames);
  for (double* block : builder.PointBlocks()) add_constant(block, kPoints);

  // The Jacobian at the solution (loss and manifolds applied) and the data
  // term's fit.
  std::vector<ceres::ResidualBlockId> residual_blocks;
  ceres_problem->GetResidualBlocks(&residual_blocks);
  const int num_data_blocks = builder.num_reprojection_terms();
  ceres::Problem::EvaluateOptions evaluate;
  evaluate.parameter_blocks = blocks;
  evaluate.residual_blocks.assign(residual_blocks.begin(),
                                  residual_blocks.begin() + num_data_blocks);
  double data_cost = 0.0;
  if (!ceres_problem->Evaluate(evaluate, &data_cost, nullptr, nullptr,
                               nullptr)) {
    return Status::Error("uncertainty: the data term cannot be evaluated");
  }
  evaluate.residual_blocks = residual_blocks;
  ceres::CRSMatrix jacobian;
  double cost = 0.0;
  if (!ceres_problem->Evaluate(evaluate, &cost, nullptr, nullptr, &jacobian)) {
    return Status::Error("uncertainty: the problem cannot be evaluated");
  }
  CHECK_EQ(jacobian.num_cols, static_cast<int>(column_map.size()));

  const int num_residuals = 2 * num_data_blocks;
  double sigma = options.noise_std;
  if (sigma == 0.0) {
    if (num_residuals <= num_parameters) {
      return Status::Error(
          "uncertainty: " + Count(num_residuals, "residuals") + " for " +
          Count(num_parameters, "parameters") +
          " leave no degrees of freedom to estimate the noise; give "
          "noise_std");
    }
    sigma = std::sqrt(2.0 * data_cost / (num_residuals - num_parameters));
  }

  // The smaller side is inverted densely, the larger one eliminated.
  const int small =
      side_size[kPoints] <= side_size[kFrames] ? kPoints : kFrames;
  const int large = 1 - small;
  const int ns = side_size[small], nl = side_size[large];
  const char* side_name[2] = {"frames'", "points'"};
  if (ns > options.max_dense_parameters) {
    return Status::Error("uncertainty: the " + std::string(side_name[small]) +
                         " side has " + Count(ns, "parameters") +
                         ", more than max_dense_parameters " +
                         std::to_string(options.max_dense_parameters));
  }
  const double bytes = 2.0 * 8.0 * static_cast<double>(nl) * ns;
  if (bytes > options.max_bytes) {
    return Status::Error(
        "uncertainty: would need " + std::to_string(bytes / (1 << 20)) +
        " MiB, more than max_bytes " +
        std::to_string(options.max_bytes / (1 << 20)) + " MiB");
  }

  // H = JᵀJ in the blocks [H_ll H_ls; H_sl H_ss]: H_ll sparse, H_ls and H_ss
  // dense.
  std::vector<Eigen::Triplet<double>> large_entries;
  Eigen::MatrixXd h_ls = Eigen::MatrixXd::Zero(nl, ns);
  Eigen::MatrixXd h_ss = Eigen::MatrixXd::Zero(ns, ns);
  std::vector<std::pair<int, double>> row_large, row_small;
  for (int r = 0; r < jacobian.num_rows; ++r) {
    row_large.clear();
    row_small.clear();
    for (int e = jacobian.rows[r]; e < jacobian.rows[r + 1]; ++e) {
      const auto [side, index] = column_map[jacobian.cols[e]];
      const double value = jacobian.values[e];
      if (index < 0 || value == 0.0) continue;
      (side == large ? row_large : row_small).emplace_back(index, value);
    }
    for (const auto& [i, vi] : row_large) large_entries.emplace_back(r, i, vi);
    // Column by column (column-major storage: a row's indices on one side
    // are mostly consecutive), each entry summed in row order.
    for (const auto& [j, vj] : row_small) {
      double* ls = h_ls.col(j).data();
      for (const auto& [i, vi] : row_large) ls[i] += vi * vj;
      double* ss = h_ss.col(j).data();
      for (const auto& [i, vi] : row_small) ss[i] += vi * vj;
    }
  }
  SparseMatrix j_large(jacobian.num_rows, nl);
  j_large.setFromTriplets(large_entries.begin(), large_entries.end());
  large_entries = {};
  const SparseMatrix h_ll = SparseMatrix(j_large.transpose()) * j_large;
  j_large = SparseMatrix();

  const auto singular = [&](int side) {
    return Status::Error(
        "uncertainty: the data and terms do not determine every parameter of "
        "the " +
        std::string(side_name[side]) +
        " side beyond the gauge (the information matrix is singular): no "
        "covariance");
  };
  Ldlt ldlt(h_ll);
  if (ldlt.info() != Eigen::Success) return singular(large);
  const double large_scale = h_ll.diagonal().cwiseAbs().maxCoeff();
  if (!(ldlt.vectorD().minCoeff() > kSingularPivot * large_scale)) {
    return singular(large);
  }
  const int threads = options.num_threads;
  Eigen::MatrixXd y(nl, ns);  // H_ll⁻¹ H_ls
  ForColumnBlocks(ns, threads, [&](int first, int count) {
    y.middleCols(first, count) = ldlt.solve(h_ls.middleCols(first, count));
  });
  // The Schur complement's lower triangle (all LLT reads).
  Eigen::MatrixXd schur = h_ss;
  ForColumnBlocks(ns, threads, [&](int first, int count) {
    schur.block(first, first, ns - first, count).noalias() -=
        h_ls.rightCols(ns - first).transpose() * y.middleCols(first, count);
  });
  h_ls = Eigen::MatrixXd();
  Eigen::LLT<Eigen::MatrixXd> llt(schur);
  const double small_scale = h_ss.diagonal().cwiseAbs().maxCoeff();
  if (llt.info() != Eigen::Success ||
      !(llt.matrixLLT().diagonal().array().square().minCoeff() >
        kSingularPivot * small_scale)) {
    return singular(small);
  }
  const Eigen::MatrixXd sigma_ss =
      llt.solve(Eigen::MatrixXd::Identity(ns, ns));  // (H⁻¹)_ss
  const Eigen::MatrixXd yt = y.transpose();          // rows of Y as columns
  y = Eigen::MatrixXd();
  Eigen::MatrixXd gt(ns, nl);  // −(H⁻¹)_ls, transposed
  ForColumnBlocks(nl, threads, [&](int first, int count) {
    gt.middleCols(first, count).noalias() =
        sigma_ss * yt.middleCols(first, count);
  });
  const SelectedInverse large_inverse(ldlt);

  // (H⁻¹)_IJ for two blocks' columns (on the large side both must be within
  // the pattern: one block, or two that a residual couples).
  const auto covariance = [&](const Columns& a, const Columns& b) {
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(a.index.size(), b.index.size());
    for (size_t i = 0; i < a.index.size(); ++i) {
      const int ai = a.index[i];
      if (ai < 0) continue;
      for (size_t j = 0; j < b.index.size(); ++j) {
        const int bj = b.index[j];
        if (bj < 0) continue;
        if (a.side == small && b.side == small) {
          out(i, j) = sigma_ss(ai, bj);
        } else if (a.side == large && b.side == small) {
          out(i, j) = -gt(bj, ai);
        } else if (a.side == small && b.side == large) {
          out(i, j) = -gt(ai, bj);
        } else {
          out(i, j) = large_inverse(ai, bj) + gt.col(ai).dot(yt.col(bj));
        }
      }
    }
    return out;
  };
  // x = H⁻¹ r for r given on both sides (columns).
  const auto solve = [&](const Eigen::MatrixXd& r_large,
                         const Eigen::MatrixXd& r_small,
                         Eigen::MatrixXd* x_large, Eigen::MatrixXd* x_small) {
    *x_small = sigma_ss * (r_small - yt * r_large);
    *x_large = ldlt.solve(r_large);
    x_large->noalias() -= yt.transpose() * *x_small;
  };
  // Rows of x (large side, small side) for a block's columns.
  const auto rows = [&](const Columns& c, const Eigen::MatrixXd& x_large,
                        const Eigen::MatrixXd& x_small) {
    const Eigen::MatrixXd& x = c.side == large ? x_large : x_small;
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(c.index.size(), x.cols());
    for (size_t i = 0; i < c.index.size(); ++i) {
      if (c.index[i] >= 0) out.row(i) = x.row(c.index[i]);
    }
    return out;
  };
  // A mean over blocks as a right-hand side: 1/count at each block's
  // coordinate i in column i.
  const auto mean_rhs = [&](const std::vector<const double*>& of, int size,
                            Eigen::MatrixXd* r_large,
                            Eigen::MatrixXd* r_small) {
    *r_large = Eigen::MatrixXd::Zero(nl, size);
    *r_small = Eigen::MatrixXd::Zero(ns, size);
    for (const double* block : of) {
      const Columns& c = columns_of.at(block);
      for (int i = 0; i < size; ++i) {
        if (c.index[i] < 0) continue;
        (c.side == large ? *r_large : *r_small)(c.index[i], i) =
            1.0 / of.size();
      }
    }
  };

  // Centring of each frame over its points: b̄ = mean_p b_p.
  std::vector<const double*> point_blocks;
  for (int p = 0; p < P; ++p) point_blocks.push_back(builder.BasisBlock(p));
  Eigen::MatrixXd r_large, r_small, mean_large, mean_small;
  mean_rhs(point_blocks, 3 * K, &r_large, &r_small);
  solve(r_large, r_small, &mean_large, &mean_small);
  const Eigen::MatrixXd mean_mean =
      r_large.transpose() * mean_large + r_small.transpose() * mean_small;
  // The rotations' mean perturbation.
  std::vector<const double*> rotation_blocks;
  for (int v = 0; v < F * M; ++v) {
    double* block = builder.RotationBlock(v / M, v % M);
    if (columns_of.count(block)) rotation_blocks.push_back(block);
  }
  Eigen::MatrixXd rot_large, rot_small;
  mean_rhs(rotation_blocks, 3, &r_large, &r_small);
  solve(r_large, r_small, &rot_large, &rot_small);
  const Eigen::Matrix3d rot_mean =
      r_large.transpose() * rot_large + r_small.transpose() * rot_small;

  const auto columns = [&](const double* block) -> const Columns& {
    static const Columns kNone;
    const auto it = columns_of.find(block);
    return it == columns_of.end() ? kNone : it->second;
  };
  const double variance = sigma * sigma;
  uncertainty->points.assign(static_cast<size_t>(F) * M * P,
                             Eigen::Matrix3d::Zero());
  uncertainty->rotations.assign(static_cast<size_t>(F) * M,
                                Eigen::Matrix3d::Zero());
  std::vector<Eigen::MatrixXd> point_cov(P), point_mean(P);
  for (int p = 0; p < P; ++p) {
    const Columns& c = columns(builder.BasisBlock(p));
    point_cov[p] = covariance(c, c);
    point_mean[p] = rows(c, mean_large, mean_small);
  }
  Eigen::MatrixXd centred_basis = model.basis;
  centred_basis.colwise() -= model.basis.rowwise().mean();
  for (int t = 0; t < F; ++t) {
    Eigen::Matrix3Xd shape = model.ShapeInObject(t);
    const Eigen::Vector3d centre = shape.rowwise().mean();
    shape.colwise() -= centre;
    for (int c = 0; c < M; ++c) {
      const int v = model.View(t, c);
      // The view's columns: δ, l_t, then s (c ≥ 1), all on the frames' side.
      const Columns& rot = columns(builder.RotationBlock(t, c));
      const Columns& weights = columns(builder.WeightsBlock(t));
      Columns view;
      view.side = kFrames;
      view.index = rot.index.empty() ? std::vector<int>(3, -1) : rot.index;
      view.index.insert(view.index.end(), weights.index.begin(),
                        weights.index.end());
      const bool with_scale = c > 0;
      if (with_scale) {
        const Columns& scale = columns(builder.ScaleBlock(t, c));
        view.index.push_back(scale.index.empty() ? -1 : scale.index[0]);
      }
      const Eigen::MatrixXd view_cov = covariance(view, view);
      const Eigen::MatrixXd view_mean = rows(view, mean_large, mean_small);
      const Eigen::Matrix3d r = model.Rotation(t, c);
      const double s = with_scale ? model.scales(v) : 1.0;
      Eigen::MatrixXd big_a(3, 3 * K);  // ∂X̃_p/∂b_p = s R (l_tᵀ ⊗ I₃)
      for (int k = 0; k < K; ++k) {
        big_a.block<3, 3>(0, 3 * k) = s * model.weights(k, t) * r;
      }
      for (int p = 0; p < P; ++p) {
        const Eigen::Vector3d x = shape.col(p);
        Eigen::MatrixXd a(3, view.index.size());
        Eigen::Matrix3d cross;
        cross << 0, -x(2), x(1), x(2), 0, -x(0), -x(1), x(0), 0;
        a.leftCols<3>() = -s * r * cross;
        for (int k = 0; k < K; ++k) {
          a.col(3 + k) = s * r * centred_basis.block<3, 1>(3 * k, p);
        }
        if (with_scale) a.col(3 + K) = r * x;
        const Columns& point = columns(builder.BasisBlock(p));
        const Eigen::MatrixXd cross_cov = covariance(view, point);
        Eigen::Matrix3d cov = a * view_cov * a.transpose() +
                              big_a * point_cov[p] * big_a.transpose();
        const Eigen::Matrix3d mixed = a * cross_cov * big_a.transpose();
        const Eigen::Matrix3d centring =
            (a * view_mean + big_a * point_mean[p]) * big_a.transpose();
        cov += mixed + mixed.transpose() - centring - centring.transpose() +
               big_a * mean_mean * big_a.transpose();
        uncertainty->points[static_cast<size_t>(v) * P + p] =
            variance * 0.5 * (cov + cov.transpose());
      }
      if (!rot.index.empty()) {
        const Eigen::Matrix3d own = covariance(rot, rot);
        const Eigen::Matrix3d to_mean = rows(rot, rot_large, rot_small);
        const Eigen::Matrix3d cov =
            own - to_mean - to_mean.transpose() + rot_mean;
        uncertainty->rotations[v] = variance * 0.5 * (cov + cov.transpose());
      }
    }
  }
  uncertainty->noise_std = sigma;
  uncertainty->noise_estimated = options.noise_std == 0.0;
  uncertainty->num_residuals = num_residuals;
  uncertainty->num_parameters = num_parameters;
  uncertainty->gauge_size = gauge_size;
  uncertainty->seconds = std::chrono::duration<double>(
                             std::chrono::steady_clock::now() - start_time)
                             .count();
  return Status::OK();
}

}  // namespace nrsfm
