#include "solvers/refine/structured_jacobian.h"

#include <glog/logging.h>

#include <algorithm>
#include <cmath>

namespace nrsfm {
namespace structured {
namespace {

using RowMap = Eigen::Map<RowMatrix, 0, Eigen::OuterStride<>>;

// The small products with one residual block's Jacobian columns (m × w,
// row-major with row stride `stride`; m is 2 or 3 here), as plain loops:
// Eigen's general kernels cost more in dispatch than in arithmetic at
// these sizes.
// out (m) += A x
inline void AddAx(const double* a, int m, int w, int stride, const double* x,
                  double* out) {
  for (int i = 0; i < m; ++i) {
    const double* row = a + i * stride;
    double sum = 0.0;
    for (int j = 0; j < w; ++j) sum += row[j] * x[j];
    out[i] += sum;
  }
}
// out (w) += Aᵀ y
inline void AddAty(const double* a, int m, int w, int stride, const double* y,
                   double* out) {
  for (int i = 0; i < m; ++i) {
    const double* row = a + i * stride;
    const double yi = y[i];
    for (int j = 0; j < w; ++j) out[j] += row[j] * yi;
  }
}

// Slot pointers for a JacobianProduct call: one per parameter block of a
// residual, on the stack for the usual few blocks.
class SlotPointers {
 public:
  explicit SlotPointers(std::size_t n) : heap_(n > kStack ? n : 0) {
    data_ = n > kStack ? heap_.data() : stack_;
    std::fill(data_, data_ + n, nullptr);
  }
  double** data() { return data_; }
  double const* const* const_data() const { return data_; }
  double*& operator[](std::size_t i) { return data_[i]; }

 private:
  static constexpr std::size_t kStack = 8;
  double* stack_[kStack];
  std::vector<double*> heap_;
  double** data_;
};

}  // namespace

StructuredJacobian::StructuredJacobian(const StructuredBlocks& blocks,
                                       int num_threads, bool allow_panel)
    : blocks_(blocks), num_threads_(num_threads) {
  r_.setZero(blocks_.num_rows);
  plus_jacobians_.resize(blocks_.blocks.size());
  rotations_.resize(blocks_.blocks.size());
  is_rotation_.assign(blocks_.blocks.size(), 0);
  for (const Residual& r : blocks_.residuals) {
    const int block = r.slot_block[BasisJacobianFactor::kRotationSlot];
    if (r.basis_factor != nullptr && block >= 0) is_rotation_[block] = 1;
  }
  if (allow_panel && panel_.Build(blocks_)) {
    use_panel_ = true;
    for (int i = 0; i < static_cast<int>(blocks_.residuals.size()); ++i) {
      if (panel_.Holds(i)) continue;
      non_panel_.push_back(i);
      if (!blocks_.residuals[i].in_grid) pass_residuals_.push_back(i);
    }
  }
  // Storage only for the Jacobians that are read: the panel's residuals
  // need none (at K 5: 26 values per observation fewer), nor the grids'
  // (their products come from their parameters, their Gram blocks and
  // column norms from the grids' sums).
  stored_.resize(blocks_.residuals.size());
  std::size_t size = 0;
  for (std::size_t i = 0; i < blocks_.residuals.size(); ++i) {
    const Residual& r = blocks_.residuals[i];
    stored_[i] = size;
    if (!Stores(static_cast<int>(i))) continue;
    size += static_cast<std::size_t>(r.m) * r.width;
    if (r.basis_factor != nullptr) size += 6;
  }
  jacobian_.assign(size, 0.0);
}

bool StructuredJacobian::Stores(int i) const {
  const Residual& r = blocks_.residuals[i];
  return !r.gram && !r.in_grid && !(use_panel_ && panel_.Holds(i));
}

void StructuredJacobian::FormSharedDerivatives(bool with_jacobian) {
  const int num_blocks = static_cast<int>(blocks_.blocks.size());
  ParallelFor(num_blocks, num_threads_, kGrain, [&](int begin, int end) {
    for (int i = begin; i < end; ++i) {
      const Block& b = blocks_.blocks[i];
      if (is_rotation_[i])
        rotations_[i] = ProjectedRotation::FromAngleAxis(b.values);
      if (with_jacobian && b.manifold != nullptr) {
        plus_jacobians_[i].resize(b.ambient, b.size);
        b.manifold->PlusJacobian(b.values, plus_jacobians_[i].data());
      }
    }
  });
}

bool StructuredJacobian::Evaluate(bool with_jacobian, double* cost) {
  const int n = static_cast<int>(blocks_.residuals.size());
  FormSharedDerivatives(with_jacobian);
  std::vector<double> partial(kReductionPieces, 0.0);
  std::vector<char> ok(kReductionPieces, 1);
  ParallelForPieces(
      n, kReductionPieces, num_threads_, kGrain,
      [&](int begin, int end, int worker) {
        std::vector<std::vector<double>> ambient;
        std::vector<double*> jacobians;
        double sum = 0.0;
        for (int i = begin; i < end; ++i) {
          const Residual& r = blocks_.residuals[i];
          double* residual = r_.data() + r.row;
          jacobians.assign(r.parameters.size(), nullptr);
          if (ambient.size() < r.parameters.size())
            ambient.resize(r.parameters.size());
          const bool store = with_jacobian && Stores(i);
          if (store) {
            for (std::size_t k = 0; k < r.parameters.size(); ++k) {
              if (r.slot_block[k] < 0 || r.slot_jcol[k] < 0) continue;
              ambient[k].resize(static_cast<std::size_t>(r.m) *
                                blocks_.blocks[r.slot_block[k]].ambient);
              jacobians[k] = ambient[k].data();
            }
          }
          bool evaluated;
          if (r.basis_factor != nullptr) {
            const int block = r.slot_block[BasisJacobianFactor::kRotationSlot];
            evaluated = r.basis_factor->EvaluateWithBasisFactor(
                r.parameters.data(), residual,
                store ? jacobians.data() : nullptr,
                store ? MutableJ(r) + static_cast<std::size_t>(r.m) * r.width
                      : nullptr,
                block >= 0 ? &rotations_[block] : nullptr);
          } else {
            evaluated = r.cost->Evaluate(r.parameters.data(), residual,
                                         store ? jacobians.data() : nullptr);
          }
          if (!evaluated) {
            ok[worker] = 0;
            return;
          }
          if (store) {
            for (std::size_t k = 0; k < r.parameters.size(); ++k) {
              if (r.slot_block[k] < 0 || r.slot_jcol[k] < 0) continue;
              const Block& b = blocks_.blocks[r.slot_block[k]];
              RowMap out(MutableJ(r) + r.slot_jcol[k], r.m, b.size,
                         Eigen::OuterStride<>(r.width));
              const Eigen::Map<const RowMatrix> in(ambient[k].data(), r.m,
                                                   b.ambient);
              if (b.manifold == nullptr) {
                out = in;
              } else {
                out.noalias() = in * plus_jacobians_[r.slot_block[k]];
              }
            }
          }
          double squared = 0.0;
          for (int j = 0; j < r.m; ++j) squared += residual[j] * residual[j];
          if (r.loss == nullptr) {
            sum += 0.5 * squared;
            continue;
          }
          // Ceres' correction of residuals and Jacobians for a robust loss
          // (Triggs et al.), so that JᵀJ and Jᵀr are its Gauss–Newton model.
          double rho[3];
          r.loss->Evaluate(squared, rho);
          sum += 0.5 * rho[0];
          const double sqrt_rho1 = std::sqrt(rho[1]);
          double scaling = sqrt_rho1, alpha_sq_norm = 0.0;
          if (squared > 0.0 && rho[2] > 0.0) {
            const double alpha =
                1.0 - std::sqrt(1.0 + 2.0 * squared * rho[2] / rho[1]);
            scaling = sqrt_rho1 / (1.0 - alpha);
            alpha_sq_norm = alpha / squared;
          }
          if (with_jacobian) {
            Eigen::Map<RowMatrix> j(MutableJ(r), r.m, r.width);
            if (alpha_sq_norm == 0.0) {
              j *= sqrt_rho1;
            } else {
              const Eigen::Map<const Eigen::VectorXd> e(residual, r.m);
              const Eigen::RowVectorXd ej = e.transpose() * j;
              j = sqrt_rho1 * (j - alpha_sq_norm * e * ej);
            }
          }
          for (int j = 0; j < r.m; ++j) residual[j] *= scaling;
        }
        partial[worker] += sum;
      });
  if (std::find(ok.begin(), ok.end(), 0) != ok.end()) return false;
  if (with_jacobian && use_panel_) panel_.Update(num_threads_);
  *cost = 0.0;
  for (double p : partial) *cost += p;
  return std::isfinite(*cost);
}

void StructuredJacobian::AddResidualJx(const Residual& r, const double* reduced,
                                       const double* eliminated,
                                       double* y) const {
  if (r.product != nullptr) {
    SlotPointers x(r.parameters.size());
    for (std::size_t k = 0; k < r.parameters.size(); ++k) {
      const int block = r.slot_block[k];
      if (block < 0) continue;
      const Block& b = blocks_.blocks[block];
      const double* source = b.eliminated ? eliminated : reduced;
      if (source != nullptr) x[k] = const_cast<double*>(source) + b.offset;
    }
    r.product->AddJacobianProduct(r.parameters.data(), x.const_data(), y);
    return;
  }
  if (reduced != nullptr) {
    for (const Segment& s : r.reduced) {
      AddAx(J(r) + s.jcol, r.m, s.width, r.width, reduced + s.col, y);
    }
  }
  if (eliminated != nullptr && r.eliminated >= 0) {
    const Block& b = blocks_.blocks[r.eliminated];
    if (r.basis_factor != nullptr) {
      // A Σ_k l_k δb_k.
      const double* x = eliminated + b.offset;
      double u[3] = {0.0, 0.0, 0.0};
      for (int k = 0; k < r.num_bases; ++k) {
        const double l = r.weights[k];
        u[0] += l * x[3 * k];
        u[1] += l * x[3 * k + 1];
        u[2] += l * x[3 * k + 2];
      }
      AddAx(Factor(r), 2, 3, 3, u, y);
      return;
    }
    AddAx(J(r) + r.eliminated_jcol, r.m, b.size, r.width, eliminated + b.offset,
          y);
  }
  if (eliminated != nullptr) {
    for (const Coupled& c : r.coupled) {
      const Block& b = blocks_.blocks[c.block];
      AddAx(J(r) + c.jcol, r.m, b.size, r.width, eliminated + b.offset, y);
    }
  }
}

void StructuredJacobian::AddResidualJty(const Residual& r, const double* y,
                                        double* reduced,
                                        double* eliminated) const {
  if (r.product != nullptr) {
    SlotPointers out(r.parameters.size());
    bool any = false;
    for (std::size_t k = 0; k < r.parameters.size(); ++k) {
      const int block = r.slot_block[k];
      if (block < 0) continue;
      const Block& b = blocks_.blocks[block];
      double* target = b.eliminated ? eliminated : reduced;
      if (target != nullptr) {
        out[k] = target + b.offset;
        any = true;
      }
    }
    if (any)
      r.product->AddJacobianTransposeProduct(r.parameters.data(), y,
                                             out.data());
    return;
  }
  if (reduced != nullptr) {
    for (const Segment& s : r.reduced) {
      AddAty(J(r) + s.jcol, r.m, s.width, r.width, y, reduced + s.col);
    }
  }
  if (eliminated != nullptr && r.eliminated >= 0) {
    const Block& b = blocks_.blocks[r.eliminated];
    if (r.basis_factor != nullptr) {
      // [l_k Aᵀ y]_k.
      double v[3] = {0.0, 0.0, 0.0};
      AddAty(Factor(r), 2, 3, 3, y, v);
      double* out = eliminated + b.offset;
      for (int k = 0; k < r.num_bases; ++k) {
        const double l = r.weights[k];
        out[3 * k] += l * v[0];
        out[3 * k + 1] += l * v[1];
        out[3 * k + 2] += l * v[2];
      }
      return;
    }
    AddAty(J(r) + r.eliminated_jcol, r.m, b.size, r.width, y,
           eliminated + b.offset);
  }
  if (eliminated != nullptr) {
    for (const Coupled& c : r.coupled) {
      const Block& b = blocks_.blocks[c.block];
      AddAty(J(r) + c.jcol, r.m, b.size, r.width, y, eliminated + b.offset);
    }
  }
}

void StructuredJacobian::MultiplyJ(const Eigen::VectorXd* reduced,
                                   const Eigen::VectorXd* eliminated,
                                   Eigen::VectorXd* rows) const {
  CHECK(!use_panel_) << "the panel's residuals have no stored Jacobian";
  rows->resize(blocks_.num_rows);
  ParallelFor(static_cast<int>(blocks_.residuals.size()), num_threads_, kGrain,
              [&](int begin, int end) {
                for (int i = begin; i < end; ++i) {
                  const Residual& r = blocks_.residuals[i];
                  double* out = rows->data() + r.row;
                  std::fill(out, out + r.m, 0.0);
                  AddResidualJx(
                      r, reduced != nullptr ? reduced->data() : nullptr,
                      eliminated != nullptr ? eliminated->data() : nullptr,
                      out);
                }
              });
}

void StructuredJacobian::Gradient(Eigen::VectorXd* reduced,
                                  Eigen::VectorXd* eliminated) const {
  const std::vector<int>* only = use_panel_ ? &non_panel_ : nullptr;
  SumOverResiduals(
      blocks_.num_reduced,
      [&](int i, double* sum) {
        const Residual& r = blocks_.residuals[i];
        AddResidualJty(r, r_.data() + r.row, sum, nullptr);
      },
      reduced, only);
  SumOverResiduals(
      blocks_.num_eliminated,
      [&](int i, double* sum) {
        const Residual& r = blocks_.residuals[i];
        AddResidualJty(r, r_.data() + r.row, nullptr, sum);
      },
      eliminated, only);
  if (use_panel_) panel_.AddGradient(r_, num_threads_, reduced, eliminated);
}

void StructuredJacobian::StepProducts(const Eigen::VectorXd& reduced,
                                      const Eigen::VectorXd& eliminated,
                                      double* dot, double* squared) const {
  const std::vector<int>* only = use_panel_ ? &non_panel_ : nullptr;
  Eigen::VectorXd sums;
  SumOverResiduals(
      2,
      [&](int i, double* sum) {
        const Residual& r = blocks_.residuals[i];
        double y[8] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        std::vector<double> heap;
        double* j = y;
        if (r.m > 8) {
          heap.assign(r.m, 0.0);
          j = heap.data();
        }
        AddResidualJx(r, reduced.data(), eliminated.data(), j);
        const double* res = r_.data() + r.row;
        for (int a = 0; a < r.m; ++a) {
          sum[0] += j[a] * res[a];
          sum[1] += j[a] * j[a];
        }
      },
      &sums, only);
  *dot = sums[0];
  *squared = sums[1];
  if (use_panel_) {
    panel_.AddStepProducts(reduced, eliminated, r_, num_threads_, dot, squared);
  }
}

void StructuredJacobian::MultiplyJtReduced(const Eigen::VectorXd& rows,
                                           Eigen::VectorXd* out) const {
  CHECK(!use_panel_) << "the panel's residuals have no stored Jacobian";
  SumOverResiduals(
      blocks_.num_reduced,
      [&](int i, double* sum) {
        const Residual& r = blocks_.residuals[i];
        AddResidualJty(r, rows.data() + r.row, sum, nullptr);
      },
      out);
}

void StructuredJacobian::MultiplyJtEliminated(const Eigen::VectorXd& rows,
                                              Eigen::VectorXd* out) const {
  CHECK(!use_panel_) << "the panel's residuals have no stored Jacobian";
  SumOverResiduals(
      blocks_.num_eliminated,
      [&](int i, double* sum) {
        const Residual& r = blocks_.residuals[i];
        AddResidualJty(r, rows.data() + r.row, nullptr, sum);
      },
      out);
}

void StructuredJacobian::MultiplyJReducedAndJtEliminated(
    const Eigen::VectorXd& reduced, Eigen::VectorXd* rows,
    Eigen::VectorXd* projected) const {
  rows->resize(blocks_.num_rows);
  SumOverResiduals(
      blocks_.num_eliminated,
      [&](int i, double* sum) {
        const Residual& r = blocks_.residuals[i];
        double* y = rows->data() + r.row;
        std::fill(y, y + r.m, 0.0);
        AddResidualJx(r, reduced.data(), nullptr, y);
        if (r.eliminated >= 0 || !r.coupled.empty())
          AddResidualJty(r, y, nullptr, sum);
      },
      projected, PassResiduals());
  if (use_panel_) panel_.ProjectReduced(reduced, num_threads_, projected);
}

void StructuredJacobian::SubtractJEliminatedAndMultiplyJtReduced(
    const Eigen::VectorXd& eliminated, Eigen::VectorXd* rows,
    Eigen::VectorXd* out) const {
  SumOverResiduals(
      blocks_.num_reduced,
      [&](int i, double* sum) {
        const Residual& r = blocks_.residuals[i];
        if (r.eliminated < 0 && r.coupled.empty()) {
          if (rows != nullptr)
            AddResidualJty(r, rows->data() + r.row, sum, nullptr);
          return;
        }
        double correction[8] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        std::vector<double> heap;
        double* c = correction;
        if (r.m > 8) {
          heap.assign(r.m, 0.0);
          c = heap.data();
        }
        AddResidualJx(r, nullptr, eliminated.data(), c);
        // y = rows − J_p e, each residual's own rows (no race), or −J_p e.
        double* y = c;
        if (rows != nullptr) {
          y = rows->data() + r.row;
          for (int a = 0; a < r.m; ++a) y[a] -= c[a];
        } else {
          for (int a = 0; a < r.m; ++a) c[a] = -c[a];
        }
        AddResidualJty(r, y, sum, nullptr);
      },
      out, PassResiduals());
  if (use_panel_) {
    panel_.AddReduced(eliminated, /*with_reduced=*/rows != nullptr,
                      num_threads_, out);
  }
}

void StructuredJacobian::ColumnSquaredNorms(Eigen::VectorXd* reduced,
                                            Eigen::VectorXd* eliminated) const {
  // One sum over the residual blocks of both parts: reduced columns first,
  // then the eliminated ones.
  const int num_reduced = blocks_.num_reduced;
  Eigen::VectorXd both;
  SumOverResiduals(
      num_reduced + blocks_.num_eliminated,
      [&](int i, double* sum) {
        const Residual& r = blocks_.residuals[i];
        double* const e_sum = sum + num_reduced;
        if (r.in_grid) return;  // SchurElimination adds the grids' part
        if (r.gram) {
          for (std::size_t k = 0; k < r.parameters.size(); ++k) {
            if (r.slot_block[k] < 0) continue;
            const Block& b = blocks_.blocks[r.slot_block[k]];
            r.product->AddGramDiagonal(r.parameters.data(), static_cast<int>(k),
                                       (b.eliminated ? e_sum : sum) + b.offset);
          }
          return;
        }
        for (const Segment& s : r.reduced) {
          Eigen::Map<Eigen::VectorXd>(sum + s.col, s.width) +=
              Cols(r, s.jcol, s.width).colwise().squaredNorm().transpose();
        }
        for (const Coupled& c : r.coupled) {
          const Block& b = blocks_.blocks[c.block];
          Eigen::Map<Eigen::VectorXd>(e_sum + b.offset, b.size) +=
              Cols(r, c.jcol, b.size).colwise().squaredNorm().transpose();
        }
        if (r.eliminated < 0) return;
        const Block& b = blocks_.blocks[r.eliminated];
        if (r.basis_factor != nullptr) {
          // Column (k, i) of l_k A: l_k² Σ_rows A(row, i)².
          const double* a = Factor(r);
          for (int k = 0; k < r.num_bases; ++k) {
            const double l2 = r.weights[k] * r.weights[k];
            for (int i = 0; i < 3; ++i) {
              e_sum[b.offset + 3 * k + i] +=
                  l2 * (a[i] * a[i] + a[3 + i] * a[3 + i]);
            }
          }
          return;
        }
        Eigen::Map<Eigen::VectorXd>(e_sum + b.offset, b.size) +=
            Cols(r, r.eliminated_jcol, b.size)
                .colwise()
                .squaredNorm()
                .transpose();
      },
      &both, use_panel_ ? &non_panel_ : nullptr);
  *reduced = both.head(num_reduced);
  *eliminated = both.tail(blocks_.num_eliminated);
  if (use_panel_) panel_.AddColumnSquaredNorms(reduced, eliminated);
}

}  // namespace structured
}  // namespace nrsfm
