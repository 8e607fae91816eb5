#include "solvers/schur_elimination.h"

#include <glog/logging.h>

#include <algorithm>

#include "core/parallel_for.h"

namespace nrsfm {
namespace structured {
namespace {

// Loops over the eliminated blocks (points) are split in pieces of this many
// (a point holds the residuals of every frame).
constexpr int kEliminatedGrain = 1;

}  // namespace

SchurElimination::SchurElimination(const StructuredBlocks& blocks,
                                   const StructuredJacobian& jacobian,
                                   int num_threads)
    : blocks_(blocks), jacobian_(jacobian), num_threads_(num_threads) {
  if (!blocks_.coupling_residuals.empty()) BuildCoupledPattern();
}

void SchurElimination::BuildCoupledPattern() {
  const int n = static_cast<int>(blocks_.eliminated_blocks.size());
  position_.assign(blocks_.blocks.size(), -1);
  for (int k = 0; k < n; ++k) position_[blocks_.eliminated_blocks[k]] = k;
  coupled_.assign(n, {});
  for (int i : blocks_.coupling_residuals) {
    const Residual& r = blocks_.residuals[i];
    for (const Coupled& a : r.coupled) {
      for (const Coupled& b : r.coupled) {
        const int pa = position_[a.block], pb = position_[b.block];
        if (pa > pb) coupled_[pb].push_back(pa);
      }
    }
  }
  std::vector<int> column_sizes;
  column_sizes.reserve(blocks_.num_eliminated);
  coupled_gram_.assign(n, {});
  for (int k = 0; k < n; ++k) {
    std::vector<int>& below = coupled_[k];
    std::sort(below.begin(), below.end());
    below.erase(std::unique(below.begin(), below.end()), below.end());
    const int size = blocks_.blocks[blocks_.eliminated_blocks[k]].size;
    int rows_below = 0;
    for (int i : below) {
      const int size_i = blocks_.blocks[blocks_.eliminated_blocks[i]].size;
      coupled_gram_[k].push_back(Eigen::MatrixXd::Zero(size_i, size));
      rows_below += size_i;
    }
    for (int c = 0; c < size; ++c)
      column_sizes.push_back(size - c + rows_below);
  }
  sparse_.resize(blocks_.num_eliminated, blocks_.num_eliminated);
  sparse_.reserve(column_sizes);
  // Inserted in the order Factor() writes the values: rows ascending within
  // each column (the eliminated offsets ascend with the position).
  for (int k = 0; k < n; ++k) {
    const Block& b = blocks_.blocks[blocks_.eliminated_blocks[k]];
    for (int c = 0; c < b.size; ++c) {
      const int col = b.offset + c;
      for (int row = col; row < b.offset + b.size; ++row) {
        sparse_.insert(row, col) = 0.0;
      }
      for (int i : coupled_[k]) {
        const Block& bi = blocks_.blocks[blocks_.eliminated_blocks[i]];
        for (int row = bi.offset; row < bi.offset + bi.size; ++row) {
          sparse_.insert(row, col) = 0.0;
        }
      }
    }
  }
  sparse_.makeCompressed();
  sparse_llt_.analyzePattern(sparse_);
}

void SchurElimination::AddCouplingGram() {
  for (std::vector<Eigen::MatrixXd>& below : coupled_gram_) {
    for (Eigen::MatrixXd& block : below) block.setZero();
  }
  for (int i : blocks_.coupling_residuals) {
    const Residual& r = blocks_.residuals[i];
    if (r.in_grid) continue;  // below, for all frames at once
    for (const Coupled& a : r.coupled) {
      const int pa = position_[a.block];
      const int size_a = blocks_.blocks[a.block].size;
      const ConstRowMap ja = jacobian_.Cols(r, a.jcol, size_a);
      for (const Coupled& b : r.coupled) {
        const int pb = position_[b.block];
        if (pa < pb) continue;
        const ConstRowMap jb =
            jacobian_.Cols(r, b.jcol, blocks_.blocks[b.block].size);
        if (pa == pb) {
          gram_[pa].noalias() += ja.transpose() * ja;
          continue;
        }
        const std::vector<int>& below = coupled_[pb];
        const auto it = std::lower_bound(below.begin(), below.end(), pa);
        coupled_gram_[pb][it - below.begin()].noalias() += ja.transpose() * jb;
      }
    }
  }
  const SmoothnessGrid& grid = blocks_.smoothness;
  if (grid.empty()) return;
  // The grid's residuals of one edge over all frames: J_bᵢᵀ J_bᵢ = J_bⱼᵀ
  // J_bⱼ = s² (G ⊗ I₃) = −J_bᵢᵀ J_bⱼ, G = Σ_t l_t l_tᵀ.
  const int k = grid.num_bases;
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(k, k);
  for (int w : grid.weights) {
    const Eigen::Map<const Eigen::VectorXd> l(blocks_.blocks[w].values, k);
    g.noalias() += l * l.transpose();
  }
  Eigen::MatrixXd g3 = Eigen::MatrixXd::Zero(3 * k, 3 * k);  // G ⊗ I₃
  for (int a = 0; a < k; ++a) {
    for (int b = 0; b < k; ++b) {
      for (int c = 0; c < 3; ++c) g3(3 * a + c, 3 * b + c) = g(a, b);
    }
  }
  grid_difference_.resize(grid.edges.size());
  grid_gram_ = Eigen::MatrixXd::Zero(k, k);
  for (std::size_t e = 0; e < grid.edges.size(); ++e) {
    const SmoothnessGrid::Edge& edge = grid.edges[e];
    const double s2 = edge.scale * edge.scale;
    const int pi = position_[edge.block_i], pj = position_[edge.block_j];
    gram_[pi].noalias() += s2 * g3;
    gram_[pj].noalias() += s2 * g3;
    const int lo = std::min(pi, pj), hi = std::max(pi, pj);
    const std::vector<int>& below = coupled_[lo];
    const auto it = std::lower_bound(below.begin(), below.end(), hi);
    coupled_gram_[lo][it - below.begin()].noalias() -= s2 * g3;
    // D_e: column k = b_i,k − b_j,k.
    const double* b_i = blocks_.blocks[edge.block_i].values;
    const double* b_j = blocks_.blocks[edge.block_j].values;
    Eigen::Matrix3Xd& d = grid_difference_[e];
    d.resize(3, k);
    for (int a = 0; a < k; ++a) {
      for (int c = 0; c < 3; ++c) d(c, a) = b_i[3 * a + c] - b_j[3 * a + c];
    }
    grid_gram_.noalias() += s2 * d.transpose() * d;
  }
}

void SchurElimination::ComputeGram() {
  gram_.resize(blocks_.eliminated_blocks.size());
  ParallelFor(
      static_cast<int>(blocks_.eliminated_blocks.size()), num_threads_,
      kEliminatedGrain, [&](int begin, int end) {
        RowMatrix stacked;
        for (int k = begin; k < end; ++k) {
          const Block& b = blocks_.blocks[blocks_.eliminated_blocks[k]];
          // Residuals with a basis factor add (l lᵀ) ⊗ (Aᵀ A)
          // directly (lower triangle).
          Eigen::MatrixXd& c = gram_[k];
          c.setZero(b.size, b.size);
          int rows = 0;
          for (const Ref& ref : blocks_.eliminated_refs[k]) {
            const Residual& r = blocks_.residuals[ref.residual];
            if (r.gram) {
              const int slot = r.EliminatedSlot();
              r.product->AddGram(r.parameters.data(), slot, slot, c.data(),
                                 static_cast<int>(c.rows()));
              continue;
            }
            if (r.basis_factor == nullptr) {
              rows += r.m;
              continue;
            }
            const double* a = jacobian_.Factor(r);
            double ata[9];
            for (int i = 0; i < 3; ++i) {
              for (int j = 0; j < 3; ++j) {
                ata[3 * i + j] = a[i] * a[j] + a[3 + i] * a[3 + j];
              }
            }
            for (int kb = 0; kb < r.num_bases; ++kb) {
              for (int ka = kb; ka < r.num_bases; ++ka) {
                const double ll = r.weights[ka] * r.weights[kb];
                for (int j = 0; j < 3; ++j) {
                  for (int i = (ka == kb ? j : 0); i < 3; ++i) {
                    c(3 * ka + i, 3 * kb + j) += ll * ata[3 * i + j];
                  }
                }
              }
            }
          }
          if (rows > 0) {
            // The block's stored Jacobian rows stacked, then one
            // symmetric rank update (the small products one by one
            // cost more).
            stacked.resize(rows, b.size);
            rows = 0;
            for (const Ref& ref : blocks_.eliminated_refs[k]) {
              const Residual& r = blocks_.residuals[ref.residual];
              if (r.basis_factor != nullptr || r.gram) continue;
              stacked.middleRows(rows, r.m) =
                  jacobian_.Cols(r, r.eliminated_jcol, b.size);
              rows += r.m;
            }
            c.selfadjointView<Eigen::Lower>().rankUpdate(stacked.transpose());
          }
          c.triangularView<Eigen::StrictlyUpper>() = c.transpose();
        }
      });
  if (!coupled_.empty()) AddCouplingGram();
}

void SchurElimination::Factor(double mu, const Eigen::VectorXd& d_eliminated) {
  if (!coupled_.empty()) {
    // The values in the order of BuildCoupledPattern's insertions.
    double* value = sparse_.valuePtr();
    for (std::size_t k = 0; k < coupled_.size(); ++k) {
      const Block& b = blocks_.blocks[blocks_.eliminated_blocks[k]];
      for (int c = 0; c < b.size; ++c) {
        *value++ = gram_[k](c, c) + mu * d_eliminated[b.offset + c];
        for (int row = c + 1; row < b.size; ++row) *value++ = gram_[k](row, c);
        for (const Eigen::MatrixXd& block : coupled_gram_[k]) {
          for (int row = 0; row < block.rows(); ++row) {
            *value++ = block(row, c);
          }
        }
      }
    }
    CHECK_EQ(value - sparse_.valuePtr(), sparse_.nonZeros());
    sparse_llt_.factorize(sparse_);
    return;
  }
  llt_.resize(blocks_.eliminated_blocks.size());
  ParallelFor(static_cast<int>(blocks_.eliminated_blocks.size()), num_threads_,
              kEliminatedGrain, [&](int begin, int end) {
                for (int k = begin; k < end; ++k) {
                  const Block& b = blocks_.blocks[blocks_.eliminated_blocks[k]];
                  Eigen::MatrixXd c = gram_[k];
                  c.diagonal() += mu * d_eliminated.segment(b.offset, b.size);
                  llt_[k].compute(c);
                }
              });
}

void SchurElimination::SolveEliminated(const Eigen::VectorXd& in,
                                       Eigen::VectorXd* out) const {
  if (!coupled_.empty()) {
    *out = sparse_llt_.solve(in);
    return;
  }
  out->resize(blocks_.num_eliminated);
  for (std::size_t k = 0; k < blocks_.eliminated_blocks.size(); ++k) {
    const Block& b = blocks_.blocks[blocks_.eliminated_blocks[k]];
    out->segment(b.offset, b.size) =
        llt_[k].solve(in.segment(b.offset, b.size));
  }
}

void SchurElimination::ApplyReduced(const Eigen::VectorXd& v, double mu,
                                    const Eigen::VectorXd& d_reduced,
                                    Eigen::VectorXd* out) const {
  // S v = J_fᵀ (J_f v − J_p C̃⁻¹ J_pᵀ J_f v) + μ D_f v, in two passes over the
  // residual blocks in the order their Jacobians are stored (they do not fit
  // in the caches, so reading them is the cost): rows = J_f v and J_pᵀ rows;
  // then J_fᵀ (rows − J_p C̃⁻¹ J_pᵀ rows).
  Eigen::VectorXd rows(blocks_.num_rows), projected, solved;
  jacobian_.MultiplyJReducedAndJtEliminated(v, &rows, &projected);
  if (!blocks_.smoothness.empty()) AddGridProjected(v, &projected);
  SolveEliminated(projected, &solved);
  jacobian_.SubtractJEliminatedAndMultiplyJtReduced(solved, &rows, out);
  if (!blocks_.smoothness.empty()) AddGridReduced(v, solved, out);
  out->array() += mu * d_reduced.array() * v.array();
}

void SchurElimination::AddGridProjected(const Eigen::VectorXd& v,
                                        Eigen::VectorXd* projected) const {
  const SmoothnessGrid& grid = blocks_.smoothness;
  const int k = grid.num_bases;
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(k, k);  // Σ_t l_t v_tᵀ
  for (int w : grid.weights) {
    const Block& b = blocks_.blocks[w];
    m.noalias() += Eigen::Map<const Eigen::VectorXd>(b.values, k) *
                   v.segment(b.offset, k).transpose();
  }
  for (std::size_t e = 0; e < grid.edges.size(); ++e) {
    const SmoothnessGrid::Edge& edge = grid.edges[e];
    const Eigen::MatrixXd p =
        edge.scale * edge.scale * grid_difference_[e] * m.transpose();
    const Eigen::Map<const Eigen::VectorXd> column(p.data(), 3 * k);
    projected->segment(blocks_.blocks[edge.block_i].offset, 3 * k) += column;
    projected->segment(blocks_.blocks[edge.block_j].offset, 3 * k) -= column;
  }
}

void SchurElimination::AddGridReduced(const Eigen::VectorXd& v,
                                      const Eigen::VectorXd& y,
                                      Eigen::VectorXd* out) const {
  const SmoothnessGrid& grid = blocks_.smoothness;
  const int k = grid.num_bases;
  Eigen::MatrixXd n = Eigen::MatrixXd::Zero(k, k);
  Eigen::Matrix3Xd y_e(3, k);
  for (std::size_t e = 0; e < grid.edges.size(); ++e) {
    const SmoothnessGrid::Edge& edge = grid.edges[e];
    const double* y_i = y.data() + blocks_.blocks[edge.block_i].offset;
    const double* y_j = y.data() + blocks_.blocks[edge.block_j].offset;
    for (int a = 0; a < k; ++a) {
      for (int c = 0; c < 3; ++c) y_e(c, a) = y_i[3 * a + c] - y_j[3 * a + c];
    }
    n.noalias() +=
        edge.scale * edge.scale * grid_difference_[e].transpose() * y_e;
  }
  for (int w : grid.weights) {
    const Block& b = blocks_.blocks[w];
    out->segment(b.offset, k).noalias() +=
        grid_gram_ * v.segment(b.offset, k) -
        n * Eigen::Map<const Eigen::VectorXd>(b.values, k);
  }
}

void SchurElimination::ReducedRightHandSide(
    const Eigen::VectorXd& gradient_reduced,
    const Eigen::VectorXd& gradient_eliminated, Eigen::VectorXd* rhs) const {
  Eigen::VectorXd solved, rows;
  SolveEliminated(gradient_eliminated, &solved);
  jacobian_.MultiplyJ(nullptr, &solved, &rows);
  jacobian_.MultiplyJtReduced(rows, rhs);
  *rhs -= gradient_reduced;
}

void SchurElimination::BackSubstitute(
    const Eigen::VectorXd& step_reduced,
    const Eigen::VectorXd& gradient_eliminated,
    Eigen::VectorXd* step_eliminated) const {
  Eigen::VectorXd jx, projected;
  jacobian_.MultiplyJ(&step_reduced, nullptr, &jx);
  jacobian_.MultiplyJtEliminated(jx, &projected);
  SolveEliminated(-gradient_eliminated - projected, step_eliminated);
}

}  // namespace structured
}  // namespace nrsfm
