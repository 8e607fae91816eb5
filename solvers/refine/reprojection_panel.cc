#include "solvers/refine/reprojection_panel.h"

#include <glog/logging.h>

#include <algorithm>
#include <unordered_map>

#include "core/math/parallel_for.h"

namespace nrsfm {
namespace structured {
namespace {

// Points per column piece at least, and pieces at most (fixed by P, so the
// products and their sums do not depend on the thread count). 16 points
// keep the pieces' products efficient and still cut the ~40 points of a
// motion-capture sequence in two, one per core (docs/performance.md).
constexpr int kColumnGrain = 16;
constexpr int kMaxPieces = 16;

// Parameter slots of a reprojection residual
// (problems/reprojection_cost_function.h).
constexpr int kTranslationSlot = 1;
constexpr int kScaleSlot = 4;

// The columns [begin, begin + width) of the panel from the eliminated
// vector `values`: point `points[begin + p]`'s 3K values as column p.
void GatherColumns(const StructuredBlocks& blocks,
                   const std::vector<int>& points, int begin, int width,
                   int size, const Eigen::VectorXd& values,
                   Eigen::MatrixXd* out) {
  out->resize(size, width);
  for (int p = 0; p < width; ++p) {
    out->col(p) = values.segment(blocks.blocks[points[begin + p]].offset, size);
  }
}

// The converse: adds column p of `in` to point `points[begin + p]`'s values.
void ScatterAddColumns(const StructuredBlocks& blocks,
                       const std::vector<int>& points, int begin,
                       const Eigen::MatrixXd& in, Eigen::VectorXd* values) {
  for (Eigen::Index p = 0; p < in.cols(); ++p) {
    values->segment(blocks.blocks[points[begin + p]].offset, in.rows()) +=
        in.col(p);
  }
}

}  // namespace

bool ReprojectionPanel::Clear() {
  std::fill(members_.begin(), members_.end(), 0);
  std::fill(column_of_.begin(), column_of_.end(), -1);
  views_.clear();
  points_.clear();
  piece_begin_.clear();
  num_entries_ = 0;
  num_bases_ = 0;
  w_.resize(0, 0);
  rows_.resize(0, 0);
  view_gram_.clear();
  return false;
}

void AddKroneckerGram(const double* sums, int num_bases, Eigen::MatrixXd* c) {
  for (int q = 0, kb = 0; kb < num_bases; ++kb) {
    for (int ka = kb; ka < num_bases; ++ka, ++q) {
      for (int e = 0, j = 0; j < 3; ++j) {
        for (int i = j; i < 3; ++i, ++e) {
          const double v = sums[6 * q + e];
          (*c)(3 * ka + i, 3 * kb + j) += v;
          if (ka != kb && i != j) (*c)(3 * ka + j, 3 * kb + i) += v;
        }
      }
    }
  }
}

bool ReprojectionPanel::Build(const StructuredBlocks& blocks) {
  blocks_ = &blocks;
  std::vector<char>* members = &members_;
  members->assign(blocks.residuals.size(), 0);
  views_.clear();
  points_.clear();
  num_entries_ = 0;
  num_bases_ = 0;
  // The parameter pointers of each view, to check that its residuals agree.
  struct Key {
    const double* translation;
    const double* weights;
    const double* scale;
  };
  std::vector<Key> keys;
  std::unordered_map<const double*, int> view_of;
  column_of_.assign(blocks.blocks.size(), -1);
  std::vector<int>& column_of = column_of_;
  struct Entry {
    int view, column, row;
    double w;
  };
  std::vector<Entry> entries;
  for (std::size_t i = 0; i < blocks.residuals.size(); ++i) {
    const Residual& r = blocks.residuals[i];
    if (r.basis_factor == nullptr || r.eliminated < 0 || r.in_grid ||
        r.product != nullptr || r.gram || r.loss != nullptr ||
        !r.coupled.empty() || r.m != 2) {
      continue;
    }
    if (num_bases_ == 0) num_bases_ = r.num_bases;
    if (r.num_bases != num_bases_) return Clear();
    const Key key = {
        r.parameters[kTranslationSlot],
        r.parameters[BasisJacobianFactor::kWeightsSlot],
        r.parameters.size() > kScaleSlot ? r.parameters[kScaleSlot] : nullptr};
    const double* rotation = r.parameters[BasisJacobianFactor::kRotationSlot];
    auto found = view_of.find(rotation);
    int view;
    if (found == view_of.end()) {
      view = static_cast<int>(views_.size());
      view_of.emplace(rotation, view);
      View v;
      v.rotation = r.slot_block[BasisJacobianFactor::kRotationSlot];
      v.translation = r.slot_block[kTranslationSlot];
      v.weights = r.slot_block[BasisJacobianFactor::kWeightsSlot];
      v.scale = key.scale != nullptr ? r.slot_block[kScaleSlot] : -1;
      v.rotation_values = rotation;
      v.weights_values = key.weights;
      v.scale_value = key.scale;
      views_.push_back(v);
      keys.push_back(key);
    } else {
      view = found->second;
      const Key& k = keys[view];
      if (k.translation != key.translation || k.weights != key.weights ||
          k.scale != key.scale) {
        return Clear();
      }
    }
    int& column = column_of[r.eliminated];
    if (column < 0) {
      column = static_cast<int>(points_.size());
      points_.push_back(r.eliminated);
    }
    entries.push_back({view, column, r.row, r.basis_factor->sqrt_weight()});
    (*members)[i] = 1;
  }
  for (View& view : views_) {
    view.blocks.clear();
    for (const int block :
         {view.rotation, view.translation, view.weights, view.scale}) {
      if (block >= 0) view.blocks.push_back(block);
    }
    // The products take translation, weights and scale in their ambient
    // coordinates.
    const auto plain = [&](int block, int size) {
      return block < 0 || (blocks.blocks[block].manifold == nullptr &&
                           blocks.blocks[block].size == size);
    };
    if (!plain(view.translation, 2) || !plain(view.weights, num_bases_) ||
        !plain(view.scale, 1)) {
      return Clear();
    }
  }
  if (entries.empty()) return Clear();
  const int v = num_views(), p = num_points();
  // The panel multiplies every entry, observed or not: measured per
  // conjugate-gradient iteration (docs/performance.md), an entry costs about
  // a fifth of a residual block, so below a fifth observed the residual
  // blocks one by one cost less (and the panel's arrays are not allocated).
  if (5 * static_cast<long long>(entries.size()) <
      static_cast<long long>(v) * p) {
    return Clear();
  }
  w_.setZero(2 * v, p);
  rows_.setConstant(v, p, -1);
  Eigen::Matrix<char, Eigen::Dynamic, Eigen::Dynamic> seen =
      Eigen::Matrix<char, Eigen::Dynamic, Eigen::Dynamic>::Zero(v, p);
  for (const Entry& e : entries) {
    if (seen(e.view, e.column)) return Clear();  // two of one view, point
    seen(e.view, e.column) = 1;
    w_(2 * e.view, e.column) = e.w;
    w_(2 * e.view + 1, e.column) = e.w;
    rows_(e.view, e.column) = e.row;
  }
  num_entries_ = static_cast<long long>(entries.size());
  const int pieces = std::max(1, std::min(kMaxPieces, p / kColumnGrain));
  piece_begin_.resize(pieces + 1);
  for (int i = 0; i <= pieces; ++i) {
    piece_begin_[i] = static_cast<int>(static_cast<long long>(p) * i / pieces);
  }
  return true;
}

void ReprojectionPanel::Update(int num_threads) {
  const int num_views = this->num_views(), k = num_bases_;
  a_.resize(num_views);
  projection_.resize(num_views);
  d_.resize(3 * static_cast<std::size_t>(num_views));
  tangent_.resize(num_views);
  n_.resize(2 * num_views, 3 * k);
  ParallelFor(num_views, num_threads, kViewGrain, [&](int begin, int end) {
    for (int v = begin; v < end; ++v) {
      const View& view = views_[v];
      const ProjectedRotation rotation =
          ProjectedRotation::FromAngleAxis(view.rotation_values);
      const double s = view.scale_value != nullptr ? *view.scale_value : 1.0;
      projection_[v] = rotation.projection;
      a_[v] = s * rotation.projection;
      for (int i = 0; i < 3; ++i) d_[3 * v + i] = s * rotation.derivative[i];
      if (view.rotation >= 0) {
        const Block& b = blocks_->blocks[view.rotation];
        if (b.manifold != nullptr) {
          RowMatrix plus(b.ambient, b.size);
          b.manifold->PlusJacobian(b.values, plus.data());
          tangent_[v] = plus;
        } else {
          tangent_[v] = Eigen::MatrixXd::Identity(3, b.size);
        }
      }
      for (int j = 0; j < k; ++j) {
        n_.block<2, 3>(2 * v, 3 * j) = view.weights_values[j] * a_[v];
      }
    }
  });
  // The Gram sums: per view the 6 entries of a_vᵀ a_v times the K(K+1)/2
  // products l_a l_b, weighted by w² per column.
  const int num_pairs = k * (k + 1) / 2;
  Eigen::MatrixXd features(6 * num_pairs, num_views);
  for (int v = 0; v < num_views; ++v) {
    const Eigen::Matrix<double, 2, 3>& a = a_[v];
    double outer[6];
    for (int q = 0, j = 0; j < 3; ++j) {
      for (int i = j; i < 3; ++i) {
        outer[q++] = a(0, i) * a(0, j) + a(1, i) * a(1, j);
      }
    }
    const double* l = views_[v].weights_values;
    for (int q = 0, kb = 0; kb < k; ++kb) {
      for (int ka = kb; ka < k; ++ka, ++q) {
        for (int e = 0; e < 6; ++e)
          features(6 * q + e, v) = outer[e] * (l[ka] * l[kb]);
      }
    }
  }
  basis_.resize(3 * k, num_points());
  ParallelFor(num_points(), num_threads, kViewGrain, [&](int begin, int end) {
    for (int p = begin; p < end; ++p) {
      basis_.col(p) = Eigen::Map<const Eigen::VectorXd>(
          blocks_->blocks[points_[p]].values, 3 * k);
    }
  });
  gram_.resize(6 * num_pairs, num_points());
  ParallelFor(NumPieces(), num_threads, 1, [&](int first, int last) {
    Eigen::MatrixXd w2;
    for (int piece = first; piece < last; ++piece) {
      const int begin = piece_begin_[piece];
      const int width = piece_begin_[piece + 1] - begin;
      SquaredWeights(begin, width, &w2);
      gram_.middleCols(begin, width).noalias() = features * w2;
    }
  });
  view_gram_.resize(num_views);
  if (ViewGramsFromMoments(num_points(), k)) {
    ViewGramsByMoments(num_threads);
  } else {
    ViewGramsDirect(num_threads);
  }
}

void ReprojectionPanel::SquaredWeights(int begin, int width,
                                       Eigen::MatrixXd* w2) const {
  w2->resize(num_views(), width);
  for (int p = 0; p < width; ++p) {
    for (int v = 0; v < num_views(); ++v) {
      const double w = w_(2 * v, begin + p);
      (*w2)(v, p) = w * w;
    }
  }
}

void ReprojectionPanel::AddColumnSquaredNorms(
    Eigen::VectorXd* reduced, Eigen::VectorXd* eliminated) const {
  for (int v = 0; v < num_views(); ++v) {
    int c = 0;
    for (const int block : views_[v].blocks) {
      const Block& b = blocks_->blocks[block];
      reduced->segment(b.offset, b.size) +=
          view_gram_[v].diagonal().segment(c, b.size);
      c += b.size;
    }
  }
  // Column (k, i) of point p: the (i, i) entry of the pair (k, k).
  const int k = num_bases_;
  constexpr int kDiagonal[3] = {0, 3, 5};
  for (int p = 0; p < num_points(); ++p) {
    double* out = eliminated->data() + blocks_->blocks[points_[p]].offset;
    for (int kk = 0; kk < k; ++kk) {
      const int q = kk * k - kk * (kk - 1) / 2;
      for (int i = 0; i < 3; ++i)
        out[3 * kk + i] += gram_(6 * q + kDiagonal[i], p);
    }
  }
}

void ReprojectionPanel::AddGram(int block, Eigen::MatrixXd* c) const {
  const int column = column_of_[block];
  if (column >= 0) AddKroneckerGram(gram_.col(column).data(), num_bases_, c);
}

void ReprojectionPanel::FormC(const Eigen::VectorXd& v, Eigen::MatrixXd* c,
                              Eigen::VectorXd* translation) const {
  const int k = num_bases_;
  c->resize(2 * num_views(), 3 * k);
  translation->setZero(2 * num_views());
  for (int i = 0; i < num_views(); ++i) {
    const View& view = views_[i];
    Eigen::Matrix<double, 2, 3> e = Eigen::Matrix<double, 2, 3>::Zero();
    if (view.rotation >= 0) {
      const Block& b = blocks_->blocks[view.rotation];
      const Eigen::Vector3d delta = tangent_[i] * v.segment(b.offset, b.size);
      for (int j = 0; j < 3; ++j) e += delta[j] * d_[3 * i + j];
    }
    if (view.scale >= 0) {
      e += v[blocks_->blocks[view.scale].offset] * projection_[i];
    }
    const double* dl = view.weights >= 0
                           ? v.data() + blocks_->blocks[view.weights].offset
                           : nullptr;
    for (int j = 0; j < k; ++j) {
      auto cj = c->block<2, 3>(2 * i, 3 * j);
      cj = view.weights_values[j] * e;
      if (dl != nullptr) cj += dl[j] * a_[i];
    }
    if (view.translation >= 0) {
      translation->segment<2>(2 * i) =
          v.segment<2>(blocks_->blocks[view.translation].offset);
    }
  }
}

void ReprojectionPanel::ProjectReduced(const Eigen::VectorXd& v,
                                       int num_threads,
                                       Eigen::VectorXd* projected) const {
  Eigen::MatrixXd c;
  Eigen::VectorXd translation;
  FormC(v, &c, &translation);
  jfv_.resize(2 * num_views(), num_points());
  ParallelFor(NumPieces(), num_threads, 1, [&](int first, int last) {
    Eigen::MatrixXd masked, out;
    for (int piece = first; piece < last; ++piece) {
      const int begin = piece_begin_[piece];
      const int width = piece_begin_[piece + 1] - begin;
      auto jfv = jfv_.middleCols(begin, width);
      jfv.noalias() = c * basis_.middleCols(begin, width);
      jfv.colwise() += translation;
      masked = w_.middleCols(begin, width).array().square() * jfv.array();
      out.noalias() = n_.transpose() * masked;
      ScatterAddColumns(*blocks_, points_, begin, out, projected);
    }
  });
}

void ReprojectionPanel::AddReduced(const Eigen::VectorXd& e, bool with_reduced,
                                   int num_threads,
                                   Eigen::VectorXd* out) const {
  const int size = 3 * num_bases_;
  std::vector<Eigen::MatrixXd> z(NumPieces());
  std::vector<Eigen::VectorXd> t(NumPieces());
  ParallelFor(NumPieces(), num_threads, 1, [&](int first, int last) {
    Eigen::MatrixXd eliminated, g;
    for (int piece = first; piece < last; ++piece) {
      const int begin = piece_begin_[piece];
      const int width = piece_begin_[piece + 1] - begin;
      GatherColumns(*blocks_, points_, begin, width, size, e, &eliminated);
      if (with_reduced) {
        g = jfv_.middleCols(begin, width);
        g.noalias() -= n_ * eliminated;
      } else {
        g.noalias() = -(n_ * eliminated);
      }
      g.array() *= w_.middleCols(begin, width).array().square();
      z[piece].noalias() = g * basis_.middleCols(begin, width).transpose();
      t[piece] = g.rowwise().sum();
    }
  });
  AddViewGradients(z, t, out);
}

void ReprojectionPanel::AddViewGradients(const std::vector<Eigen::MatrixXd>& z,
                                         const std::vector<Eigen::VectorXd>& t,
                                         Eigen::VectorXd* out) const {
  const int k = num_bases_;
  Eigen::MatrixXd zs = z[0];
  Eigen::VectorXd ts = t[0];
  for (int piece = 1; piece < NumPieces(); ++piece) {
    zs += z[piece];
    ts += t[piece];
  }
  for (int i = 0; i < num_views(); ++i) {
    const View& view = views_[i];
    const auto zi = zs.middleRows(2 * i, 2);
    if (view.weights >= 0) {
      double* g = out->data() + blocks_->blocks[view.weights].offset;
      for (int j = 0; j < k; ++j) {
        g[j] += a_[i].cwiseProduct(zi.middleCols<3>(3 * j)).sum();
      }
    }
    if (view.rotation >= 0 || view.scale >= 0) {
      // Σ_j l_j Z_j: the gradient of ω and s are its products with d_i, Π R.
      Eigen::Matrix<double, 2, 3> sum = Eigen::Matrix<double, 2, 3>::Zero();
      for (int j = 0; j < k; ++j) {
        sum += view.weights_values[j] * zi.middleCols<3>(3 * j);
      }
      if (view.rotation >= 0) {
        Eigen::Vector3d ambient;
        for (int j = 0; j < 3; ++j) {
          ambient[j] = d_[3 * i + j].cwiseProduct(sum).sum();
        }
        const Block& b = blocks_->blocks[view.rotation];
        out->segment(b.offset, b.size).noalias() +=
            tangent_[i].transpose() * ambient;
      }
      if (view.scale >= 0) {
        (*out)[blocks_->blocks[view.scale].offset] +=
            projection_[i].cwiseProduct(sum).sum();
      }
    }
    if (view.translation >= 0) {
      out->segment<2>(blocks_->blocks[view.translation].offset) +=
          ts.segment<2>(2 * i);
    }
  }
}

void ReprojectionPanel::AddGradient(const Eigen::VectorXd& residuals,
                                    int num_threads, Eigen::VectorXd* reduced,
                                    Eigen::VectorXd* eliminated) const {
  const int views = num_views();
  std::vector<Eigen::MatrixXd> z(NumPieces());
  std::vector<Eigen::VectorXd> t(NumPieces());
  ParallelFor(NumPieces(), num_threads, 1, [&](int first, int last) {
    Eigen::MatrixXd g, projected;
    for (int piece = first; piece < last; ++piece) {
      const int begin = piece_begin_[piece];
      const int width = piece_begin_[piece + 1] - begin;
      // G = w ⊙ r: Jᵀ r = J̃ᵀ (w ⊙ r), J = w J̃.
      g.resize(2 * views, width);
      for (int p = 0; p < width; ++p) {
        for (int v = 0; v < views; ++v) {
          const int row = rows_(v, begin + p);
          const double w = w_(2 * v, begin + p);
          g(2 * v, p) = row >= 0 ? w * residuals[row] : 0.0;
          g(2 * v + 1, p) = row >= 0 ? w * residuals[row + 1] : 0.0;
        }
      }
      projected.noalias() = n_.transpose() * g;
      ScatterAddColumns(*blocks_, points_, begin, projected, eliminated);
      z[piece].noalias() = g * basis_.middleCols(begin, width).transpose();
      t[piece] = g.rowwise().sum();
    }
  });
  AddViewGradients(z, t, reduced);
}

void ReprojectionPanel::AddStepProducts(const Eigen::VectorXd& reduced,
                                        const Eigen::VectorXd& eliminated,
                                        const Eigen::VectorXd& residuals,
                                        int num_threads, double* dot,
                                        double* squared) const {
  Eigen::MatrixXd c;
  Eigen::VectorXd translation;
  FormC(reduced, &c, &translation);
  const int size = 3 * num_bases_, views = num_views();
  std::vector<double> dots(NumPieces(), 0.0), squares(NumPieces(), 0.0);
  ParallelFor(NumPieces(), num_threads, 1, [&](int first, int last) {
    Eigen::MatrixXd step, y;
    for (int piece = first; piece < last; ++piece) {
      const int begin = piece_begin_[piece];
      const int width = piece_begin_[piece + 1] - begin;
      GatherColumns(*blocks_, points_, begin, width, size, eliminated, &step);
      // J δ / w = C s_p + δT + N δb_p.
      y.noalias() = c * basis_.middleCols(begin, width);
      y.colwise() += translation;
      y.noalias() += n_ * step;
      double d = 0.0, q = 0.0;
      for (int p = 0; p < width; ++p) {
        for (int v = 0; v < views; ++v) {
          const int row = rows_(v, begin + p);
          if (row < 0) continue;
          const double w = w_(2 * v, begin + p);
          const double y0 = w * y(2 * v, p), y1 = w * y(2 * v + 1, p);
          d += y0 * residuals[row] + y1 * residuals[row + 1];
          q += y0 * y0 + y1 * y1;
        }
      }
      dots[piece] = d;
      squares[piece] = q;
    }
  });
  for (int piece = 0; piece < NumPieces(); ++piece) {
    *dot += dots[piece];
    *squared += squares[piece];
  }
}

}  // namespace structured
}  // namespace nrsfm
