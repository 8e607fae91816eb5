#include "solvers/refine/band_preconditioner.h"

#include <glog/logging.h>

#include <algorithm>
#include <cstddef>

#include "core/math/parallel_for.h"

namespace nrsfm {
namespace structured {
namespace {

// Loops over the frame groups are split in pieces of at least this many (a
// group holds a view's residuals).
constexpr int kGroupGrain = 8;

// out (wa × wb, column-major with leading dimension ld) += Aᵀ B for the
// m × wa and m × wb row-major blocks A, B (row strides stride_a, stride_b),
// as plain loops: Eigen's general kernels cost more in dispatch than in
// arithmetic at these sizes (m is 2 or 3 here).
inline void AddAtB(const double* a, int m, int wa, int stride_a,
                   const double* b, int wb, int stride_b, double* out, int ld) {
  for (int r = 0; r < m; ++r) {
    const double* ar = a + r * stride_a;
    const double* br = b + r * stride_b;
    for (int j = 0; j < wb; ++j) {
      const double bj = br[j];
      double* column = out + static_cast<std::ptrdiff_t>(j) * ld;
      for (int i = 0; i < wa; ++i) column[i] += ar[i] * bj;
    }
  }
}

}  // namespace

BandPreconditioner::BandPreconditioner(const StructuredBlocks& blocks,
                                       const StructuredJacobian& jacobian,
                                       int num_threads)
    : blocks_(blocks), jacobian_(jacobian), num_threads_(num_threads) {
  grid_rows_.assign(blocks_.num_groups(), {});
  for (std::size_t g = 0; g < blocks_.grids.size(); ++g) {
    const BilinearGrid& grid = blocks_.grids[g];
    for (std::size_t q = 0; q < grid.rows.size(); ++q) {
      std::vector<int> groups;
      for (const BilinearGrid::Term& term : grid.rows[q]) {
        groups.push_back(blocks_.blocks[term.block].group);
      }
      std::sort(groups.begin(), groups.end());
      groups.erase(std::unique(groups.begin(), groups.end()), groups.end());
      for (int group : groups) {
        grid_rows_[group].emplace_back(static_cast<int>(g),
                                       static_cast<int>(q));
      }
    }
  }
  panel_views_.assign(blocks_.num_groups(), {});
  const ReprojectionPanel* panel = jacobian_.panel();
  if (panel == nullptr) return;
  for (int v = 0; v < panel->num_views(); ++v) {
    std::vector<int> groups;
    for (const int block : panel->ViewBlocks(v)) {
      groups.push_back(blocks_.blocks[block].group);
    }
    std::sort(groups.begin(), groups.end());
    groups.erase(std::unique(groups.begin(), groups.end()), groups.end());
    for (const int group : groups) {
      if (group >= 0) {
        panel_views_[group].push_back(v);
      } else {
        shared_panel_views_.push_back(v);
      }
    }
  }
}

void BandPreconditioner::AddViewGram(int view, int g) {
  const ReprojectionPanel& panel = *jacobian_.panel();
  const std::vector<int>& view_blocks = panel.ViewBlocks(view);
  const Eigen::MatrixXd& gram = panel.ViewGram(view);
  const int num_group_columns = blocks_.num_group_columns;
  for (std::size_t ia = 0, ca = 0; ia < view_blocks.size(); ++ia) {
    const Block& a = blocks_.blocks[view_blocks[ia]];
    for (std::size_t ib = 0, cb = 0; ib < view_blocks.size(); ++ib) {
      const Block& b = blocks_.blocks[view_blocks[ib]];
      const auto part = gram.block(ca, cb, a.size, b.size);
      if (g < 0) {  // the corner: shared against shared
        if (a.group < 0 && b.group < 0) {
          corner_.block(a.offset - num_group_columns,
                        b.offset - num_group_columns, a.size, b.size) += part;
        }
      } else if (a.group != g) {
        // Its rows are another group's (or the corner's).
      } else if (b.group < 0) {
        border_.block(a.offset, b.offset - num_group_columns, a.size, b.size) +=
            part;
      } else if (g - b.group >= 0) {  // the band's lower triangle of blocks
        DCHECK_LE(g - b.group, blocks_.band);
        band_[g][g - b.group].block(a.offset - blocks_.group_offset[g],
                                    b.offset - blocks_.group_offset[b.group],
                                    a.size, b.size) += part;
      }
      cb += b.size;
    }
    ca += a.size;
  }
}

void BandPreconditioner::Build(double mu, const Eigen::VectorXd& d_reduced,
                               const std::vector<Eigen::MatrixXd>& grid_grams) {
  const int num_groups = blocks_.num_groups();
  const int num_group_columns = blocks_.num_group_columns;
  const int num_shared = blocks_.num_shared();
  const int band = blocks_.band;
  const std::vector<int>& group_offset = blocks_.group_offset;
  const ReprojectionPanel* panel = jacobian_.panel();
  band_.assign(num_groups, std::vector<Eigen::MatrixXd>(band + 1));
  border_ = Eigen::MatrixXd::Zero(num_group_columns, num_shared);
  ParallelFor(num_groups, num_threads_, kGroupGrain, [&](int begin, int end) {
    for (int g = begin; g < end; ++g) {
      for (int d = 0; d <= band && g - d >= 0; ++d) {
        band_[g][d] = Eigen::MatrixXd::Zero(blocks_.GroupSize(g),
                                            blocks_.GroupSize(g - d));
      }
      for (const Ref& ref : blocks_.group_refs[g]) {
        if (panel != nullptr && panel->Holds(ref.residual)) continue;
        const Residual& r = blocks_.residuals[ref.residual];
        const Segment& a = r.reduced[ref.segment];
        if (r.gram) {
          AddGram(r, a, g);
          continue;
        }
        const double* j = jacobian_.J(r);
        const int row_a = a.col - group_offset[g];
        for (const Segment& b : r.reduced) {
          if (b.group < 0) {
            AddAtB(j + a.jcol, r.m, a.width, r.width, j + b.jcol, b.width,
                   r.width, &border_(a.col, b.col - num_group_columns),
                   border_.rows());
            continue;
          }
          const int d = g - b.group;
          if (d < 0) continue;  // the lower triangle of the band only
          Eigen::MatrixXd& block = band_[g][d];
          AddAtB(j + a.jcol, r.m, a.width, r.width, j + b.jcol, b.width,
                 r.width, &block(row_a, b.col - group_offset[b.group]),
                 block.rows());
        }
      }
      // The grids' rows with a weights block a in group g: σ_a σ_b H_grid
      // against each weights block b of the row in a group ≤ g (the band's
      // lower triangle of blocks; a diagonal block is filled in full, as
      // above).
      for (const int v : panel_views_[g]) AddViewGram(v, g);
      for (const auto& [grid, q] : grid_rows_[g]) {
        const Eigen::MatrixXd& h = grid_grams[grid];
        const std::vector<BilinearGrid::Term>& row =
            blocks_.grids[grid].rows[q];
        for (const BilinearGrid::Term& a : row) {
          const Block& ba = blocks_.blocks[a.block];
          if (ba.group != g) continue;
          for (const BilinearGrid::Term& b : row) {
            const Block& bb = blocks_.blocks[b.block];
            if (bb.group > g) continue;
            band_[g][g - bb.group].block(
                ba.offset - group_offset[g], bb.offset - group_offset[bb.group],
                h.rows(), h.cols()) += a.sign * b.sign * h;
          }
        }
      }
      band_[g][0].diagonal() +=
          mu * d_reduced.segment(group_offset[g], blocks_.GroupSize(g));
    }
  });
  corner_ = Eigen::MatrixXd::Zero(num_shared, num_shared);
  Eigen::MatrixXd& corner = corner_;
  for (const int v : shared_panel_views_) AddViewGram(v, -1);
  for (int i : blocks_.residuals_with_shared) {
    if (panel != nullptr && panel->Holds(i)) continue;
    const Residual& r = blocks_.residuals[i];
    if (r.gram) {
      // The corner's column of slot k's block, or -1 when it is not shared.
      const auto corner_column = [&](std::size_t k) {
        const int block = r.slot_block[k];
        if (block < 0 || blocks_.blocks[block].eliminated ||
            blocks_.blocks[block].group >= 0) {
          return -1;
        }
        return blocks_.blocks[block].offset - num_group_columns;
      };
      for (std::size_t ka = 0; ka < r.parameters.size(); ++ka) {
        const int ia = corner_column(ka);
        if (ia < 0) continue;
        for (std::size_t kb = 0; kb < r.parameters.size(); ++kb) {
          const int ib = corner_column(kb);
          if (ib < 0) continue;
          r.product->AddGram(r.parameters.data(), static_cast<int>(ka),
                             static_cast<int>(kb), &corner(ia, ib),
                             static_cast<int>(corner.rows()));
        }
      }
      continue;
    }
    for (const Segment& a : r.reduced) {
      if (a.group >= 0) continue;
      for (const Segment& b : r.reduced) {
        if (b.group >= 0) continue;
        corner
            .block(a.col - num_group_columns, b.col - num_group_columns,
                   a.width, b.width)
            .noalias() += jacobian_.Cols(r, a.jcol, a.width).transpose() *
                          jacobian_.Cols(r, b.jcol, b.width);
      }
    }
  }
  corner.diagonal() += mu * d_reduced.tail(num_shared);
  // Block-band Cholesky: band_[g][d] ← L(g, g − d).
  for (int g = 0; g < num_groups; ++g) {
    for (int d = std::min(band, g); d >= 1; --d) {
      Eigen::MatrixXd m = band_[g][d];
      for (int e = d + 1; e <= band && g - e >= 0; ++e) {
        m.noalias() -= band_[g][e] * band_[g - d][e - d].transpose();
      }
      band_[g][d] = band_[g - d][0]
                        .triangularView<Eigen::Lower>()
                        .solve(m.transpose())
                        .transpose();
    }
    Eigen::MatrixXd m = band_[g][0];
    for (int d = 1; d <= band && g - d >= 0; ++d) {
      m.noalias() -= band_[g][d] * band_[g][d].transpose();
    }
    Eigen::LLT<Eigen::MatrixXd> llt(m);
    if (llt.info() != Eigen::Success) {
      // A preconditioner only needs to be positive definite.
      m.diagonal().array() +=
          1e-10 * m.diagonal().cwiseAbs().maxCoeff() + 1e-300;
      llt.compute(m);
    }
    band_[g][0] = llt.matrixL();
  }
  if (num_shared > 0) {
    border_solved_ = border_;
    BandSolve(&border_solved_);
    corner_llt_.compute(corner - border_.transpose() * border_solved_);
  }
}

void BandPreconditioner::AddGram(const Residual& r, const Segment& a, int g) {
  const int num_group_columns = blocks_.num_group_columns;
  for (std::size_t ka = 0; ka < r.parameters.size(); ++ka) {
    if (r.slot_block[ka] < 0) continue;
    const Block& ba = blocks_.blocks[r.slot_block[ka]];
    if (ba.eliminated || ba.offset < a.col || ba.offset >= a.col + a.width)
      continue;
    const int row_a = ba.offset - blocks_.group_offset[g];
    for (std::size_t kb = 0; kb < r.parameters.size(); ++kb) {
      if (r.slot_block[kb] < 0) continue;
      const Block& bb = blocks_.blocks[r.slot_block[kb]];
      if (bb.eliminated) continue;
      if (bb.group < 0) {
        r.product->AddGram(r.parameters.data(), static_cast<int>(ka),
                           static_cast<int>(kb),
                           &border_(ba.offset, bb.offset - num_group_columns),
                           static_cast<int>(border_.rows()));
        continue;
      }
      const int d = g - bb.group;
      if (d < 0) continue;  // the lower triangle of the band only
      Eigen::MatrixXd& block = band_[g][d];
      r.product->AddGram(
          r.parameters.data(), static_cast<int>(ka), static_cast<int>(kb),
          &block(row_a, bb.offset - blocks_.group_offset[bb.group]),
          static_cast<int>(block.rows()));
    }
  }
}

template <typename Matrix>
void BandPreconditioner::BandSolve(Matrix* x) const {
  const int num_groups = blocks_.num_groups();
  const int band = blocks_.band;
  const std::vector<int>& group_offset = blocks_.group_offset;
  for (int g = 0; g < num_groups; ++g) {
    auto xg = x->middleRows(group_offset[g], blocks_.GroupSize(g));
    for (int d = 1; d <= band && g - d >= 0; ++d) {
      xg.noalias() -= band_[g][d] * x->middleRows(group_offset[g - d],
                                                  blocks_.GroupSize(g - d));
    }
    band_[g][0].triangularView<Eigen::Lower>().solveInPlace(xg);
  }
  for (int g = num_groups - 1; g >= 0; --g) {
    auto xg = x->middleRows(group_offset[g], blocks_.GroupSize(g));
    for (int d = 1; d <= band && g + d < num_groups; ++d) {
      xg.noalias() -=
          band_[g + d][d].transpose() *
          x->middleRows(group_offset[g + d], blocks_.GroupSize(g + d));
    }
    band_[g][0].transpose().triangularView<Eigen::Upper>().solveInPlace(xg);
  }
}

void BandPreconditioner::Apply(const Eigen::VectorXd& in,
                               Eigen::VectorXd* out) const {
  const int num_group_columns = blocks_.num_group_columns;
  const int num_shared = blocks_.num_shared();
  Eigen::VectorXd x = in.head(num_group_columns);
  BandSolve(&x);
  out->resize(blocks_.num_reduced);
  if (num_shared == 0) {
    *out = x;
    return;
  }
  // [A B; Bᵀ C]: y = (C − Bᵀ A⁻¹ B)⁻¹ (b − Bᵀ A⁻¹ a), x = A⁻¹ a − A⁻¹ B y.
  const Eigen::VectorXd y =
      corner_llt_.solve(in.tail(num_shared) - border_.transpose() * x);
  out->head(num_group_columns) = x.col(0) - border_solved_ * y;
  out->tail(num_shared) = y;
}

}  // namespace structured
}  // namespace nrsfm
