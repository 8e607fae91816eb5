// The views' Gram blocks J_vᵀ J_v of a ReprojectionPanel (the
// preconditioner's diagonal blocks, solvers/refine/reprojection_panel.h):
// from the points' moments or residual by residual, whichever costs less.
#include <Eigen/Core>
#include <vector>

#include "core/math/parallel_for.h"
#include "solvers/refine/reprojection_panel.h"

namespace nrsfm {
namespace structured {

int ReprojectionPanel::ViewColumns(const View& view) const {
  int columns = 0;
  for (const int block : view.blocks) columns += blocks_->blocks[block].size;
  return columns;
}

void ReprojectionPanel::ViewGramsByMoments(int num_threads) {
  const int k = num_bases_, num_views = this->num_views();
  // The points' mean c: the moments below are of s_p − c, so that points
  // far from the origin lose no precision to cancellation.
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(3 * k);
  for (int p = 0; p < num_points(); ++p) mean += basis_.col(p);
  mean /= num_points();
  // Per piece, per view the part of M_v = Σ_p w² s̄_p s̄_pᵀ (s̄ = [s_p − c; 1],
  // its lower triangle by columns).
  const int n = 3 * k + 1, num_products = n * (n + 1) / 2;
  std::vector<Eigen::MatrixXd> moments(NumPieces());
  ParallelFor(NumPieces(), num_threads, 1, [&](int first, int last) {
    Eigen::MatrixXd w2, products;
    Eigen::VectorXd s_bar(n);
    for (int piece = first; piece < last; ++piece) {
      const int begin = piece_begin_[piece];
      const int width = piece_begin_[piece + 1] - begin;
      SquaredWeights(begin, width, &w2);
      products.resize(width, num_products);
      s_bar[n - 1] = 1.0;
      for (int p = 0; p < width; ++p) {
        s_bar.head(n - 1) = basis_.col(begin + p) - mean;
        for (int q = 0, j = 0; j < n; ++j) {
          for (int i = j; i < n; ++i, ++q) products(p, q) = s_bar[i] * s_bar[j];
        }
      }
      moments[piece].noalias() = w2 * products;
    }
  });
  for (int piece = 1; piece < NumPieces(); ++piece)
    moments[0] += moments[piece];
  ParallelFor(num_views, num_threads, kViewGrain, [&](int begin, int end) {
    Eigen::MatrixXd m(n, n), phi;
    for (int v = begin; v < end; ++v) {
      for (int q = 0, j = 0; j < n; ++j) {
        for (int i = j; i < n; ++i, ++q) m(i, j) = m(j, i) = moments[0](v, q);
      }
      const View& view = views_[v];
      const int columns = ViewColumns(view);
      Eigen::MatrixXd& g = view_gram_[v];
      g.setZero(columns, columns);
      const double* l = view.weights_values;
      for (int row = 0; row < 2; ++row) {
        // Φ: J̃'s row `row` = Φ s̄ (one row of Φ per column of J̃).
        phi.setZero(columns, n);
        int c = 0;
        for (const int block : view.blocks) {
          const Block& b = blocks_->blocks[block];
          if (block == view.rotation) {
            for (int i = 0; i < 3; ++i) {
              for (int kk = 0; kk < k; ++kk) {
                for (int x = 0; x < 3; ++x) {
                  const double u = l[kk] * d_[3 * v + i](row, x);
                  for (int t = 0; t < b.size; ++t)
                    phi(c + t, 3 * kk + x) += tangent_[v](i, t) * u;
                }
              }
            }
          } else if (block == view.translation) {
            phi(c + row, n - 1) = 1.0;
          } else if (block == view.weights) {
            for (int kk = 0; kk < k; ++kk)
              phi.block<1, 3>(c + kk, 3 * kk) = a_[v].row(row);
          } else {  // the scale
            for (int kk = 0; kk < k; ++kk)
              phi.block<1, 3>(c, 3 * kk) = l[kk] * projection_[v].row(row);
          }
          c += b.size;
        }
        // Φ [s_p; 1] = Φ' [s_p − c; 1]: the constant column takes Φ_s c.
        phi.col(n - 1) += phi.leftCols(n - 1) * mean;
        g.noalias() += phi * m * phi.transpose();
      }
    }
  });
}

bool ReprojectionPanel::ViewGramsFromMoments(int num_points, int num_bases) {
  // Multiply-adds per view (n = K + 6 columns at most): the moments' product
  // and Φ M Φᵀ, against J̃ formed and its Gram updated point by point.
  const double k = num_bases, n = k + 6.0, s = 3.0 * k + 1.0;
  const double moments =
      num_points * s * (s + 1.0) / 2.0 + 2.0 * (n * s * s + n * n * s);
  const double direct =
      num_points * (3.0 * k + 2.0 * (3.0 * k + n + n * (n + 1.0) / 2.0 + 21.0));
  return moments < direct;
}

void ReprojectionPanel::ViewGramsDirect(int num_threads) {
  const int k = num_bases_, num_points = this->num_points();
  ParallelFor(num_views(), num_threads, 1, [&](int begin, int end) {
    Eigen::Matrix3Xd x(3, num_points), ambient(3, num_points);
    Eigen::MatrixXd jt;
    for (int v = begin; v < end; ++v) {
      const View& view = views_[v];
      const double* l = view.weights_values;
      const int columns = ViewColumns(view);
      // X_p = Σ_k l_k b_pk of every point.
      x = l[0] * basis_.topRows<3>();
      for (int kk = 1; kk < k; ++kk) x += l[kk] * basis_.middleRows<3>(3 * kk);
      Eigen::MatrixXd& g = view_gram_[v];
      g.setZero(columns, columns);
      jt.resize(columns, num_points);
      for (int row = 0; row < 2; ++row) {
        // J̃ᵀ's row `row` of every point, as columns, times w.
        int c = 0;
        for (const int block : view.blocks) {
          const Block& b = blocks_->blocks[block];
          if (block == view.rotation) {
            Eigen::Matrix3d d;
            for (int i = 0; i < 3; ++i) d.row(i) = d_[3 * v + i].row(row);
            ambient.noalias() = d * x;
            jt.middleRows(c, b.size).noalias() =
                tangent_[v].transpose() * ambient;
          } else if (block == view.translation) {
            jt.row(c + row).setOnes();
            jt.row(c + 1 - row).setZero();
          } else if (block == view.weights) {
            for (int kk = 0; kk < k; ++kk) {
              jt.row(c + kk).noalias() =
                  a_[v].row(row) * basis_.middleRows<3>(3 * kk);
            }
          } else {  // the scale
            jt.row(c).noalias() = projection_[v].row(row) * x;
          }
          c += b.size;
        }
        jt.array().rowwise() *= w_.row(2 * v).array();
        g.selfadjointView<Eigen::Lower>().rankUpdate(jt);
      }
      g.triangularView<Eigen::StrictlyUpper>() = g.transpose();
    }
  });
}

}  // namespace structured
}  // namespace nrsfm
