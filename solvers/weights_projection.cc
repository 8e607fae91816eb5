#include "solvers/weights_projection.h"

#include <glog/logging.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "core/parallel_for.h"
#include "problems/jacobian_product.h"

namespace nrsfm {
namespace structured {
namespace {

// Views and groups per piece of a parallel loop.
constexpr int kGrain = 32;

using ConstBasis = Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic>>;

// The residual's BilinearForm when it has one that fits K and 3 residuals
// (no robust loss), else false.
bool FormOf(const Residual& r, int num_bases, BilinearForm* form) {
  if (r.loss != nullptr || r.product == nullptr || r.m != 3 ||
      !r.product->GetBilinearForm(form)) {
    return false;
  }
  return form->num_bases == num_bases &&
         form->signs.size() == r.parameters.size() &&
         form->is_weights.size() == r.parameters.size() &&
         (form->mask.empty() ||
          static_cast<int>(form->mask.size()) == num_bases);
}

}  // namespace

void WeightsProjection::Build(const StructuredBlocks& blocks,
                              const ReprojectionPanel& panel) {
  blocks_ = &blocks;
  panel_ = &panel;
  num_bases_ = panel.num_bases();
  projects_ = balances_ = false;
  weights_.clear();
  groups_.clear();
  basis_slots_.clear();
  masks_.clear();
  const int num_blocks = static_cast<int>(blocks.blocks.size());
  const int k = num_bases_;
  if (panel.num_views() == 0 || k < 1) return;
  bool projects = true, mixing = true;

  // The weights blocks: the views' and the BilinearForm residuals'.
  std::vector<char> is_weights(num_blocks, 0), is_basis(num_blocks, 0);
  for (int v = 0; v < panel.num_views(); ++v) {
    const int b = panel.ViewWeightsBlock(v);
    if (b >= 0) {
      is_weights[b] = 1;
    } else {
      mixing = false;
    }
  }
  const int num_residuals = static_cast<int>(blocks.residuals.size());
  std::vector<BilinearForm> forms(num_residuals);
  std::vector<char> has_form(num_residuals, 0);
  for (int i = 0; i < num_residuals; ++i) {
    const Residual& r = blocks.residuals[i];
    if (panel.Holds(i) || !FormOf(r, k, &forms[i])) continue;
    has_form[i] = 1;
    for (std::size_t s = 0; s < r.parameters.size(); ++s) {
      if (r.slot_block[s] >= 0 && forms[i].is_weights[s])
        is_weights[r.slot_block[s]] = 1;
    }
  }
  for (int b = 0; b < num_blocks; ++b) {
    const Block& block = blocks.blocks[b];
    if (block.eliminated) {
      is_basis[b] = 1;
      if (block.size != 3 * k || block.manifold != nullptr) mixing = false;
    }
    if (is_weights[b] &&
        (block.eliminated || block.manifold != nullptr || block.size != k)) {
      return;  // not a weights block as the panel reads it
    }
  }
  index_of_.assign(num_blocks, -1);
  for (int b = 0; b < num_blocks; ++b) {
    if (is_weights[b]) {
      index_of_[b] = static_cast<int>(weights_.size());
      weights_.push_back(b);
    }
  }
  view_index_.resize(panel.num_views());
  for (int v = 0; v < panel.num_views(); ++v) {
    const int b = panel.ViewWeightsBlock(v);
    view_index_[v] = b >= 0 ? index_of_[b] : -1;
  }

  // Every residual that holds weights or basis blocks.
  std::map<std::pair<int, int>, int> group_of;
  for (int i = 0; i < num_residuals; ++i) {
    const Residual& r = blocks.residuals[i];
    if (panel.Holds(i)) continue;
    bool holds_weights = false, holds_basis = false;
    for (std::size_t s = 0; s < r.parameters.size(); ++s) {
      const int b = r.slot_block[s];
      if (b < 0) continue;
      holds_weights = holds_weights || is_weights[b];
      holds_basis = holds_basis || is_basis[b];
    }
    if (!has_form[i]) {
      if (holds_weights) projects = mixing = false;
      if (holds_basis) mixing = false;
      continue;
    }
    const BilinearForm& form = forms[i];
    if (!form.mask.empty()) mixing = false;
    int lo = -1, hi = -1;
    for (std::size_t s = 0; s < r.parameters.size(); ++s) {
      const int b = r.slot_block[s];
      if (b < 0) {
        mixing = false;  // a constant block the mixing would have to move
        continue;
      }
      if (!form.is_weights[s]) continue;
      const int w = index_of_[b];
      if (lo < 0) {
        lo = hi = w;
      } else if (w == lo - 1 && hi == lo) {
        lo = w;
      } else if (w == hi + 1 && hi == lo) {
        hi = w;
      } else if (w != lo && w != hi) {
        projects = false;  // not a chain of neighbouring frames
      }
    }
    if (lo < 0) continue;
    Term term;
    term.residual = i;
    term.scale = form.scale;
    term.first_basis = static_cast<int>(basis_slots_.size());
    for (std::size_t s = 0; s < r.parameters.size(); ++s) {
      if (!form.is_weights[s]) {
        basis_slots_.emplace_back(static_cast<int>(s), form.signs[s]);
        ++term.num_basis;
      } else if (r.slot_block[s] >= 0) {
        term.sigma[index_of_[r.slot_block[s]] == lo ? 0 : 1] += form.signs[s];
      }
    }
    if (!form.mask.empty()) {
      term.mask = static_cast<int>(masks_.size());
      masks_.push_back(form.mask);
    }
    const auto found = group_of.find({lo, hi});
    if (found == group_of.end()) {
      group_of.emplace(std::make_pair(lo, hi),
                       static_cast<int>(groups_.size()));
      groups_.push_back(Group{lo, hi, {term}});
    } else {
      groups_[found->second].terms.push_back(term);
    }
  }
  std::sort(groups_.begin(), groups_.end(), [](const Group& a, const Group& b) {
    return std::make_pair(a.lo, a.hi) < std::make_pair(b.lo, b.hi);
  });
  projects_ = projects && !weights_.empty();
  balances_ = projects_ && mixing;
}

bool WeightsProjection::Project(const Eigen::VectorXd& residuals,
                                int num_threads) const {
  if (!projects_) return false;
  const int k = num_bases_, n = static_cast<int>(weights_.size());
  const StructuredBlocks& blocks = *blocks_;
  const ReprojectionPanel& panel = *panel_;
  // The normal equations H δ = −g, H block tridiagonal: diagonal blocks and
  // the blocks (i, i − 1) below them.
  std::vector<Eigen::MatrixXd> diagonal(n, Eigen::MatrixXd::Zero(k, k));
  std::vector<Eigen::MatrixXd> below(n, Eigen::MatrixXd::Zero(k, k));
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(k, n);

  // The panel's views: J_l = w a_v B_p (2 × K) for every observed point.
  const int num_views = panel.num_views(), num_points = panel.num_points();
  std::vector<Eigen::MatrixXd> view_h(num_views);
  Eigen::MatrixXd view_g(k, num_views);
  ParallelFor(num_views, num_threads, kGrain, [&](int begin, int end) {
    Eigen::MatrixXd stacked(2 * num_points, k);
    Eigen::VectorXd rows(2 * num_points);
    for (int v = begin; v < end; ++v) {
      if (view_index_[v] < 0) continue;
      const Eigen::Matrix<double, 2, 3> a = panel.CurrentProjection(v);
      int m = 0;
      for (int p = 0; p < num_points; ++p) {
        const int row = panel.Row(v, p);
        if (row < 0) continue;
        const ConstBasis basis(blocks.blocks[panel.PointBlock(p)].values, 3, k);
        stacked.middleRows<2>(m).noalias() = panel.Weight(v, p) * a * basis;
        rows.segment<2>(m) = residuals.segment<2>(row);
        m += 2;
      }
      const auto jl = stacked.topRows(m);
      view_h[v].noalias() = jl.transpose() * jl;
      view_g.col(v).noalias() = jl.transpose() * rows.head(m);
    }
  });
  for (int v = 0; v < num_views; ++v) {
    const int w = view_index_[v];
    if (w < 0) continue;
    diagonal[w] += view_h[v];
    g.col(w) += view_g.col(v);
  }

  // The BilinearForm residuals, r = s D λ: J_l = s σ_j D diag(m) for weights
  // block j; per group, its blocks (lo, lo), (hi, hi), (hi, lo). DᵀD of a
  // residual with one basis block b_p (the temporal shape prior) is
  // (s τ)² B_pᵀ B_p, formed once per basis block.
  const int num_blocks = static_cast<int>(blocks.blocks.size());
  std::vector<Eigen::MatrixXd> basis_gram(num_blocks);
  ParallelFor(num_blocks, num_threads, 4 * kGrain, [&](int begin, int end) {
    for (int b = begin; b < end; ++b) {
      if (!blocks.blocks[b].eliminated || blocks.blocks[b].size != 3 * k)
        continue;
      const ConstBasis basis(blocks.blocks[b].values, 3, k);
      basis_gram[b].noalias() = basis.transpose() * basis;
    }
  });
  const int num_groups = static_cast<int>(groups_.size());
  std::vector<Eigen::MatrixXd> group_h(3 * num_groups);
  Eigen::MatrixXd group_g(k, 2 * num_groups);
  ParallelFor(num_groups, num_threads, kGrain, [&](int begin, int end) {
    Eigen::Matrix<double, 3, Eigen::Dynamic> d(3, k);
    Eigen::MatrixXd dtd(k, k), pending(k, k);
    Eigen::VectorXd dtr(k);
    for (int q = begin; q < end; ++q) {
      const Group& group = groups_[q];
      Eigen::MatrixXd* h = &group_h[3 * q];
      for (int j = 0; j < 3; ++j) h[j].setZero(k, k);
      group_g.middleCols<2>(2 * q).setZero();
      // DᵀD of consecutive terms with the same σ summed before they are
      // scaled by the σ products (the temporal shape prior: every term).
      double pending_sigma[2] = {0.0, 0.0};
      bool has_pending = false;
      const auto flush = [&]() {
        if (!has_pending) return;
        h[0] += (pending_sigma[0] * pending_sigma[0]) * pending;
        h[1] += (pending_sigma[1] * pending_sigma[1]) * pending;
        h[2] += (pending_sigma[1] * pending_sigma[0]) * pending;
        has_pending = false;
      };
      for (const Term& term : group.terms) {
        const Residual& r = blocks.residuals[term.residual];
        const Eigen::Vector3d rows = residuals.segment<3>(r.row);
        const std::pair<int, double>* slots =
            basis_slots_.data() + term.first_basis;
        const int one = term.num_basis == 1 ? r.slot_block[slots[0].first] : -1;
        if (one >= 0 && term.mask < 0 && basis_gram[one].size() > 0) {
          // D = s τ B_p: DᵀD = (s τ)² B_pᵀ B_p.
          const double st = term.scale * slots[0].second;
          const ConstBasis basis(r.parameters[slots[0].first], 3, k);
          dtr.noalias() = st * (basis.transpose() * rows);
          if (has_pending && term.sigma[0] == pending_sigma[0] &&
              term.sigma[1] == pending_sigma[1]) {
            pending += (st * st) * basis_gram[one];
            group_g.col(2 * q) += term.sigma[0] * dtr;
            group_g.col(2 * q + 1) += term.sigma[1] * dtr;
            continue;
          }
          dtd.noalias() = (st * st) * basis_gram[one];
        } else {
          d.setZero();
          for (int j = 0; j < term.num_basis; ++j) {
            d += slots[j].second *
                 ConstBasis(r.parameters[slots[j].first], 3, k);
          }
          d *= term.scale;
          if (term.mask >= 0) {
            for (int c = 0; c < k; ++c) d.col(c) *= masks_[term.mask][c];
          }
          dtd.noalias() = d.transpose() * d;
          dtr.noalias() = d.transpose() * rows;
        }
        if (has_pending && (term.sigma[0] != pending_sigma[0] ||
                            term.sigma[1] != pending_sigma[1])) {
          flush();
        }
        if (!has_pending) {
          pending = dtd;
          pending_sigma[0] = term.sigma[0];
          pending_sigma[1] = term.sigma[1];
          has_pending = true;
        } else {
          pending += dtd;
        }
        group_g.col(2 * q) += term.sigma[0] * dtr;
        group_g.col(2 * q + 1) += term.sigma[1] * dtr;
      }
      flush();
    }
  });
  for (int q = 0; q < num_groups; ++q) {
    const Group& group = groups_[q];
    if (group.lo == group.hi) {
      // One weights block: σ was summed into sigma[0].
      diagonal[group.lo] += group_h[3 * q];
      g.col(group.lo) += group_g.col(2 * q);
      continue;
    }
    diagonal[group.lo] += group_h[3 * q];
    diagonal[group.hi] += group_h[3 * q + 1];
    below[group.hi] += group_h[3 * q + 2];
    g.col(group.lo) += group_g.col(2 * q);
    g.col(group.hi) += group_g.col(2 * q + 1);
  }

  // Block Cholesky of the tridiagonal H: L_i L_iᵀ = H_ii − X_i X_iᵀ,
  // X_i = H_(i,i−1) L_(i−1)⁻ᵀ; then the two triangular sweeps.
  // A ridge of 1e-10 of the mean diagonal entry: weights that no residual
  // constrains (a frame with fewer points than K/2 and no temporal term) do
  // not move instead of making H singular.
  double trace = 0.0;
  for (int i = 0; i < n; ++i) trace += diagonal[i].trace();
  const double ridge = 1e-10 * trace / (static_cast<double>(n) * k);
  // L_i and X_iᵀ per block.
  std::vector<Eigen::MatrixXd> lower(n), xt(n);
  Eigen::LLT<Eigen::MatrixXd> llt(k);
  Eigen::MatrixXd a(k, k);
  for (int i = 0; i < n; ++i) {
    a = diagonal[i];
    a.diagonal().array() += ridge;
    if (i > 0) {
      xt[i] = below[i].transpose();
      lower[i - 1].triangularView<Eigen::Lower>().solveInPlace(xt[i]);
      a.noalias() -= xt[i].transpose() * xt[i];
    }
    llt.compute(a);
    if (llt.info() != Eigen::Success) return false;
    lower[i] = llt.matrixL();
  }
  Eigen::MatrixXd delta = -g;
  for (int i = 0; i < n; ++i) {
    if (i > 0) delta.col(i).noalias() -= xt[i].transpose() * delta.col(i - 1);
    lower[i].triangularView<Eigen::Lower>().solveInPlace(delta.col(i));
  }
  for (int i = n - 1; i >= 0; --i) {
    if (i + 1 < n) delta.col(i).noalias() -= xt[i + 1] * delta.col(i + 1);
    lower[i].triangularView<Eigen::Lower>().transpose().solveInPlace(
        delta.col(i));
  }
  if (!delta.allFinite()) return false;
  for (int i = 0; i < n; ++i) {
    Eigen::Map<Eigen::VectorXd>(blocks.blocks[weights_[i]].values, k) +=
        delta.col(i);
  }
  return true;
}

bool WeightsProjection::Balance(Eigen::MatrixXd* applied) const {
  if (!balances_) return false;
  const int k = num_bases_, n = static_cast<int>(weights_.size());
  const StructuredBlocks& blocks = *blocks_;
  Eigen::MatrixXd w(k, n);
  for (int i = 0; i < n; ++i) {
    w.col(i) =
        Eigen::Map<const Eigen::VectorXd>(blocks.blocks[weights_[i]].values, k);
  }
  Eigen::MatrixXd gb = Eigen::MatrixXd::Zero(k, k);
  for (const Block& b : blocks.blocks) {
    if (!b.eliminated) continue;
    const ConstBasis basis(b.values, 3, k);
    gb.noalias() += basis.transpose() * basis;
  }
  const Eigen::MatrixXd gw = w * w.transpose();
  // P = M⁻½ (M½ N M½)½ M⁻½ with M = G_w, N = G_b solves P M P = N; with
  // A = P½: A G_w Aᵀ = A⁻ᵀ G_b A⁻¹.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> em(gw);
  if (em.info() != Eigen::Success ||
      em.eigenvalues().minCoeff() <= 1e-12 * em.eigenvalues().maxCoeff())
    return false;
  const Eigen::MatrixXd m_half = em.operatorSqrt();
  const Eigen::MatrixXd m_inv_half = em.operatorInverseSqrt();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ec(m_half * gb * m_half);
  if (ec.info() != Eigen::Success ||
      ec.eigenvalues().minCoeff() <= 1e-12 * ec.eigenvalues().maxCoeff())
    return false;
  const Eigen::MatrixXd p = m_inv_half * ec.operatorSqrt() * m_inv_half;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ep(p);
  const Eigen::MatrixXd a = ep.operatorSqrt();
  if (!a.allFinite()) return false;
  Mix(a);
  if (applied != nullptr) *applied = a;
  return true;
}

void WeightsProjection::Mix(const Eigen::MatrixXd& a) const {
  const int k = num_bases_;
  CHECK_EQ(a.rows(), k);
  CHECK_EQ(a.cols(), k);
  const StructuredBlocks& blocks = *blocks_;
  for (const int b : weights_) {
    Eigen::Map<Eigen::VectorXd> l(blocks.blocks[b].values, k);
    const Eigen::VectorXd old = l;
    l.noalias() = a * old;
  }
  // b_p as 3 × K (column c: basis shape c): b_p → b_p A⁻¹.
  const Eigen::MatrixXd inverse = a.partialPivLu().inverse();
  Eigen::Matrix<double, 3, Eigen::Dynamic> old(3, k);
  for (const Block& b : blocks.blocks) {
    if (!b.eliminated) continue;
    Eigen::Map<Eigen::Matrix<double, 3, Eigen::Dynamic>> basis(b.values, 3, k);
    old = basis;
    basis.noalias() = old * inverse;
  }
}

}  // namespace structured
}  // namespace nrsfm
