#include "solvers/refine/schur_elimination.h"

#include <glog/logging.h>

#include <Eigen/CholmodSupport>
#include <algorithm>

#include "core/math/parallel_for.h"

namespace nrsfm {
namespace structured {
namespace {

// Loops over the eliminated blocks (points) are split in pieces of this many
// (a point holds the residuals of every frame).
constexpr int kEliminatedGrain = 1;

}  // namespace

class SchurElimination::CoupledFactor {
 public:
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> llt;
};

SchurElimination::~SchurElimination() = default;

SchurElimination::SchurElimination(const StructuredBlocks& blocks,
                                   const StructuredJacobian& jacobian,
                                   int num_threads)
    : blocks_(blocks), jacobian_(jacobian), num_threads_(num_threads) {
  const int n = static_cast<int>(blocks_.eliminated_blocks.size());
  position_.assign(blocks_.blocks.size(), -1);
  for (int k = 0; k < n; ++k) position_[blocks_.eliminated_blocks[k]] = k;
  bool coupling = !blocks_.coupling_residuals.empty();
  for (const BilinearGrid& grid : blocks_.grids) {
    for (const BilinearGrid::Column& column : grid.columns) {
      coupling = coupling || column.points.size() > 1;
    }
  }
  if (coupling) BuildCoupledPattern();
}

void SchurElimination::BuildCoupledPattern() {
  const int n = static_cast<int>(blocks_.eliminated_blocks.size());
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
  for (const BilinearGrid& grid : blocks_.grids) {
    for (const BilinearGrid::Column& column : grid.columns) {
      for (const BilinearGrid::Term& a : column.points) {
        for (const BilinearGrid::Term& b : column.points) {
          const int pa = position_[a.block], pb = position_[b.block];
          if (pa > pb) coupled_[pb].push_back(pa);
        }
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
  coupled_factor_ = std::make_unique<CoupledFactor>();
  coupled_factor_->llt.cholmod().print = 0;  // the library prints nothing
  coupled_factor_->llt.analyzePattern(sparse_);
}

void SchurElimination::AddCouplingGram() {
  for (std::vector<Eigen::MatrixXd>& below : coupled_gram_) {
    for (Eigen::MatrixXd& block : below) block.setZero();
  }
  for (int i : blocks_.coupling_residuals) {
    const Residual& r = blocks_.residuals[i];
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
}

Eigen::MatrixXd& SchurElimination::CoupledGram(int a, int b) {
  const int lo = std::min(a, b), hi = std::max(a, b);
  const std::vector<int>& below = coupled_[lo];
  const auto it = std::lower_bound(below.begin(), below.end(), hi);
  DCHECK(it != below.end() && *it == hi);
  return coupled_gram_[lo][it - below.begin()];
}

void SchurElimination::AddGridGram(int g) {
  // The grid's residuals of one column e over all rows q: J_bᵢᵀ J_bⱼ =
  // τ_i τ_j s_e² (G ⊗ I₃), G = Σ_q λ_q λ_qᵀ (K × K, the same for every column).
  const BilinearGrid& grid = blocks_.grids[g];
  const int k = grid.num_bases;
  Eigen::MatrixXd& lambdas = grid_lambdas_[g];  // λ_q per row, masked
  lambdas.resize(k, static_cast<Eigen::Index>(grid.rows.size()));
  Eigen::VectorXd lambda(k);
  for (std::size_t q = 0; q < grid.rows.size(); ++q) {
    RowCombination(grid.rows[q], k, &lambda);
    lambdas.col(q) = grid.mask.cwiseProduct(lambda);
  }
  const Eigen::MatrixXd outer = lambdas * lambdas.transpose();
  Eigen::MatrixXd g3 = Eigen::MatrixXd::Zero(3 * k, 3 * k);  // G ⊗ I₃
  for (int a = 0; a < k; ++a) {
    for (int b = 0; b < k; ++b) {
      for (int c = 0; c < 3; ++c) g3(3 * a + c, 3 * b + c) = outer(a, b);
    }
  }
  std::vector<Eigen::Matrix3Xd>& difference = grid_difference_[g];
  difference.resize(grid.columns.size());
  Eigen::MatrixXd& h = grid_gram_[g];
  h = Eigen::MatrixXd::Zero(k, k);
  for (std::size_t e = 0; e < grid.columns.size(); ++e) {
    const BilinearGrid::Column& column = grid.columns[e];
    const double s2 = column.scale * column.scale;
    Eigen::Matrix3Xd& d = difference[e];  // D_e = Σ_i τ_i B_i
    d = Eigen::Matrix3Xd::Zero(3, k);
    for (const BilinearGrid::Term& a : column.points) {
      d += a.sign * Eigen::Map<const Eigen::Matrix3Xd>(
                        blocks_.blocks[a.block].values, 3, k);
      const int pa = position_[a.block];
      for (const BilinearGrid::Term& b : column.points) {
        const int pb = position_[b.block];
        if (pa == pb) {
          gram_[pa].noalias() += (a.sign * b.sign * s2) * g3;
        } else if (pa > pb) {
          CoupledGram(pa, pb).noalias() += (a.sign * b.sign * s2) * g3;
        }
      }
    }
    h.noalias() += s2 * d.transpose() * d;
  }
  h = grid.mask.asDiagonal() * h * grid.mask.asDiagonal();  // M H M
}

void SchurElimination::AddGridColumnSquaredNorms(
    Eigen::VectorXd* reduced, Eigen::VectorXd* eliminated) const {
  for (std::size_t g = 0; g < blocks_.grids.size(); ++g) {
    const BilinearGrid& grid = blocks_.grids[g];
    const int k = grid.num_bases;
    const Eigen::VectorXd h = grid_gram_[g].diagonal();
    const Eigen::VectorXd lambda2 = grid_lambdas_[g].rowwise().squaredNorm();
    for (const std::vector<BilinearGrid::Term>& row : grid.rows) {
      for (const BilinearGrid::Term& term : row) {
        reduced->segment(blocks_.blocks[term.block].offset, k) +=
            term.sign * term.sign * h;
      }
    }
    for (const BilinearGrid::Column& column : grid.columns) {
      const double s2 = column.scale * column.scale;
      for (const BilinearGrid::Term& term : column.points) {
        double* out = eliminated->data() + blocks_.blocks[term.block].offset;
        const double f = s2 * term.sign * term.sign;
        for (int a = 0; a < k; ++a) {
          for (int c = 0; c < 3; ++c) out[3 * a + c] += f * lambda2(a);
        }
      }
    }
  }
}

void SchurElimination::RowCombination(
    const std::vector<BilinearGrid::Term>& row, int k, Eigen::VectorXd* out,
    const Eigen::VectorXd* v) const {
  out->setZero(k);
  for (const BilinearGrid::Term& term : row) {
    const Block& b = blocks_.blocks[term.block];
    if (v == nullptr) {
      *out += term.sign * Eigen::Map<const Eigen::VectorXd>(b.values, k);
    } else {
      *out += term.sign * v->segment(b.offset, k);
    }
  }
}

void SchurElimination::ComputeGram() {
  gram_.resize(blocks_.eliminated_blocks.size());
  ParallelFor(
      static_cast<int>(blocks_.eliminated_blocks.size()), num_threads_,
      kEliminatedGrain, [&](int begin, int end) {
        RowMatrix stacked, outer, products;
        Eigen::MatrixXd sums;
        const ReprojectionPanel* panel = jacobian_.panel();
        for (int k = begin; k < end; ++k) {
          const int b_index = blocks_.eliminated_blocks[k];
          const Block& b = blocks_.blocks[b_index];
          Eigen::MatrixXd& c = gram_[k];
          c.setZero(b.size, b.size);
          // Residuals with a basis factor add (l lᵀ) ⊗ (Aᵀ A), l the frame's
          // K weights: one row per residual of the 6 entries of Aᵀ A
          // (`outer`) and of the K(K+1)/2 products l_a l_b, a ≥ b
          // (`products`), and their product outerᵀ products (one matrix
          // product instead of a small update per residual).
          // The panel's residuals: their part at once (AddGram).
          const auto in_panel = [panel](const Ref& ref) {
            return panel != nullptr && panel->Holds(ref.residual);
          };
          int rows = 0, factored = 0;
          for (const Ref& ref : blocks_.eliminated_refs[k]) {
            const Residual& r = blocks_.residuals[ref.residual];
            if (r.basis_factor != nullptr && !in_panel(ref)) ++factored;
          }
          const int num_bases = b.size / 3;
          const int num_pairs = num_bases * (num_bases + 1) / 2;
          if (factored > 0) {
            outer.resize(factored, 6);
            products.resize(factored, num_pairs);
          }
          factored = 0;
          for (const Ref& ref : blocks_.eliminated_refs[k]) {
            const Residual& r = blocks_.residuals[ref.residual];
            if (in_panel(ref)) continue;
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
            DCHECK_EQ(r.num_bases, num_bases);
            const double* a = jacobian_.Factor(r);
            double* o = outer.row(factored).data();
            for (int q = 0, j = 0; j < 3; ++j) {
              for (int i = j; i < 3; ++i) {
                o[q++] = a[i] * a[j] + a[3 + i] * a[3 + j];
              }
            }
            double* l = products.row(factored).data();
            for (int q = 0, kb = 0; kb < num_bases; ++kb) {
              for (int ka = kb; ka < num_bases; ++ka) {
                l[q++] = r.weights[ka] * r.weights[kb];
              }
            }
            ++factored;
          }
          if (factored > 0) {
            sums.noalias() = outer.transpose() * products;
            AddKroneckerGram(sums.data(), num_bases, &c);
          }
          if (panel != nullptr) panel->AddGram(b_index, &c);
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
  grid_difference_.resize(blocks_.grids.size());
  grid_gram_.resize(blocks_.grids.size());
  grid_lambdas_.resize(blocks_.grids.size());
  for (std::size_t g = 0; g < blocks_.grids.size(); ++g) {
    AddGridGram(static_cast<int>(g));
  }
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
    coupled_factor_->llt.factorize(sparse_);
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
    *out = coupled_factor_->llt.solve(in);
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
  for (std::size_t g = 0; g < blocks_.grids.size(); ++g) {
    AddGridProjected(static_cast<int>(g), v, &projected);
  }
  SolveEliminated(projected, &solved);
  jacobian_.SubtractJEliminatedAndMultiplyJtReduced(solved, &rows, out);
  for (std::size_t g = 0; g < blocks_.grids.size(); ++g) {
    AddGridReduced(static_cast<int>(g), v, solved, out);
  }
  out->array() += mu * d_reduced.array() * v.array();
}

void SchurElimination::AddGridProjected(int g, const Eigen::VectorXd& v,
                                        Eigen::VectorXd* projected) const {
  const BilinearGrid& grid = blocks_.grids[g];
  const int k = grid.num_bases;
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(k, k);  // Σ_q λ_q ν_qᵀ
  Eigen::VectorXd nu(k);
  for (std::size_t q = 0; q < grid.rows.size(); ++q) {
    RowCombination(grid.rows[q], k, &nu, &v);
    nu.array() *= grid.mask.array();
    m.noalias() += grid_lambdas_[g].col(q) * nu.transpose();
  }
  for (std::size_t e = 0; e < grid.columns.size(); ++e) {
    const BilinearGrid::Column& column = grid.columns[e];
    const Eigen::MatrixXd p =
        column.scale * column.scale * grid_difference_[g][e] * m.transpose();
    const Eigen::Map<const Eigen::VectorXd> flat(p.data(), 3 * k);
    for (const BilinearGrid::Term& a : column.points) {
      projected->segment(blocks_.blocks[a.block].offset, 3 * k) +=
          a.sign * flat;
    }
  }
}

void SchurElimination::AddGridReduced(int g, const Eigen::VectorXd& v,
                                      const Eigen::VectorXd& y,
                                      Eigen::VectorXd* out) const {
  const BilinearGrid& grid = blocks_.grids[g];
  const int k = grid.num_bases;
  Eigen::MatrixXd n = Eigen::MatrixXd::Zero(k, k);  // Σ_e s_e² D_eᵀ Y_e
  Eigen::Matrix3Xd y_e(3, k);
  for (std::size_t e = 0; e < grid.columns.size(); ++e) {
    const BilinearGrid::Column& column = grid.columns[e];
    y_e.setZero();
    for (const BilinearGrid::Term& a : column.points) {
      y_e += a.sign * Eigen::Map<const Eigen::Matrix3Xd>(
                          y.data() + blocks_.blocks[a.block].offset, 3, k);
    }
    n.noalias() +=
        column.scale * column.scale * grid_difference_[g][e].transpose() * y_e;
  }
  Eigen::VectorXd nu(k), z(k);
  for (std::size_t q = 0; q < grid.rows.size(); ++q) {
    const std::vector<BilinearGrid::Term>& row = grid.rows[q];
    RowCombination(row, k, &nu, &v);
    // σ_j M (H M ν̃_q − N λ_q) = σ_j (M H M ν̃_q − M N λ_q), ν̃_q unmasked.
    z.noalias() = grid_gram_[g] * nu;
    z.array() -= grid.mask.array() * (n * grid_lambdas_[g].col(q)).array();
    for (const BilinearGrid::Term& term : row) {
      out->segment(blocks_.blocks[term.block].offset, k) += term.sign * z;
    }
  }
}

void SchurElimination::ReducedRightHandSide(
    const Eigen::VectorXd& gradient_reduced,
    const Eigen::VectorXd& gradient_eliminated, Eigen::VectorXd* rhs) const {
  // J_fᵀ J_p C̃⁻¹ g_p = −J_fᵀ (−J_p C̃⁻¹ g_p): the second pass of
  // ApplyReduced() without the first.
  Eigen::VectorXd solved, out;
  SolveEliminated(gradient_eliminated, &solved);
  jacobian_.SubtractJEliminatedAndMultiplyJtReduced(solved, nullptr, &out);
  const Eigen::VectorXd none = Eigen::VectorXd::Zero(blocks_.num_reduced);
  for (std::size_t g = 0; g < blocks_.grids.size(); ++g) {
    AddGridReduced(static_cast<int>(g), none, solved, &out);
  }
  *rhs = -out - gradient_reduced;
}

void SchurElimination::BackSubstitute(
    const Eigen::VectorXd& step_reduced,
    const Eigen::VectorXd& gradient_eliminated,
    Eigen::VectorXd* step_eliminated) const {
  // J_pᵀ J_f δ_f: the first pass of ApplyReduced().
  Eigen::VectorXd rows, projected;
  jacobian_.MultiplyJReducedAndJtEliminated(step_reduced, &rows, &projected);
  for (std::size_t g = 0; g < blocks_.grids.size(); ++g) {
    AddGridProjected(static_cast<int>(g), step_reduced, &projected);
  }
  SolveEliminated(-gradient_eliminated - projected, step_eliminated);
}

}  // namespace structured
}  // namespace nrsfm
