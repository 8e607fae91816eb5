#include "solvers/structured_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <unordered_map>

#include <Eigen/Cholesky>
#include <glog/logging.h>
#include <Eigen/Core>
#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>

#include "core/parallel_for.h"
#include "problems/jacobian_product.h"
#include "problems/reprojection_cost_function.h"

namespace nrsfm {
namespace {

using Clock = std::chrono::steady_clock;
using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using ConstRowMap = Eigen::Map<const RowMatrix, 0, Eigen::OuterStride<>>;
using RowMap = Eigen::Map<RowMatrix, 0, Eigen::OuterStride<>>;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Loops are split over threads in pieces of at least this many items
// (core/parallel_for.h): residual blocks are cheap, a frame group holds a
// view's residuals, an eliminated block (a point) those of every frame.
constexpr int kGrain = 64;
// Sums over residuals (the cost, Jᵀr and Jᵀ products) are added in this many
// fixed pieces, whatever the thread count, so that the result does not
// depend on it (core/parallel_for.h); at most this many threads share them.
constexpr int kReductionPieces = 16;
constexpr int kGroupGrain = 8;
constexpr int kEliminatedGrain = 1;

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

// out (wa × wb, column-major with leading dimension ld) += Aᵀ B for the
// m × wa and m × wb row-major blocks A, B (row strides stride_a, stride_b).
inline void AddAtB(const double* a, int m, int wa, int stride_a, const double* b, int wb,
                   int stride_b, double* out, int ld) {
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

struct Block {
  double* values = nullptr;
  int ambient = 0;  // values in memory
  int size = 0;     // tangent size: columns of the Jacobian
  const ceres::Manifold* manifold = nullptr;
  bool eliminated = false;
  int group = -1;   // frame group of a reduced block, -1 for a shared one
  int offset = 0;   // in the reduced or the eliminated vector
};

// Columns [col, col + width) of a residual block's Jacobian, which sit at
// [jcol, jcol + width) of its stored row-major m × width_total matrix.
struct Segment {
  int col = 0;
  int width = 0;
  int jcol = 0;
  int group = -1;  // -1: shared block
};

struct Residual {
  const ceres::CostFunction* cost = nullptr;
  const ceres::LossFunction* loss = nullptr;
  int m = 0;          // residuals
  int row = 0;        // first row in r
  int width = 0;      // columns of the stored Jacobian
  std::size_t jac = 0;  // start in the Jacobian buffer
  std::vector<double*> parameters;
  std::vector<int> slot_block;  // Block index per parameter, -1 = constant
  std::vector<int> slot_jcol;   // column of the slot in the stored Jacobian
  std::vector<Segment> reduced;  // merged per group
  int eliminated = -1;           // Block index, -1 = none
  int eliminated_jcol = 0;
  // Products with its Jacobian from its parameters (problems/jacobian_product.h),
  // used in the conjugate gradients instead of the stored Jacobian.
  const JacobianProduct* product = nullptr;
  // A reprojection residual without a robust loss whose eliminated block is
  // its basis block: that block's Jacobian l_k · A is not stored, only A
  // (2 × 3 at factors_[factor]), and l is read from the weights block
  // (problems/reprojection_cost_function.h, BasisJacobianFactor).
  const BasisJacobianFactor* basis_factor = nullptr;
  std::size_t factor = 0;
  const double* weights = nullptr;
  int num_bases = 0;
  // The product also provides its Gram blocks (JacobianProduct::ProvidesGram):
  // no Jacobian is stored for this residual at all.
  bool gram = false;
};

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

// A reference from a target (group, shared block or eliminated block) to the
// residual segments that touch it.
struct Ref {
  int residual;
  int segment;  // index into Residual::reduced, or -1 for the eliminated part
};

class Solver {
 public:
  Solver(const StructuredSolverOptions& options, ceres::Problem* problem)
      : options_(options), problem_(problem) {}

  bool Setup(const StructuredLayout& layout, std::string* error);
  bool Run(StructuredSolverSummary* summary);

 private:
  int GroupSize(int g) const { return group_offset_[g + 1] - group_offset_[g]; }
  double* J(const Residual& r) { return jacobian_.data() + r.jac; }
  const double* J(const Residual& r) const { return jacobian_.data() + r.jac; }
  ConstRowMap Cols(const Residual& r, int jcol, int width) const {
    return ConstRowMap(J(r) + jcol, r.m, width, Eigen::OuterStride<>(r.width));
  }

  bool Evaluate(bool with_jacobian, double* cost);
  // y (r.m values) += J_r x for the reduced and eliminated parts given
  // (null = zero), and the transposed products into the parts wanted.
  void AddResidualJx(const Residual& r, const double* reduced, const double* eliminated,
                     double* y) const;
  void AddResidualJty(const Residual& r, const double* y, double* reduced,
                      double* eliminated) const;
  // *out (size values) = Σ_i body(i, sum) over the residual blocks in storage
  // order, each thread into its own sum, added in thread order.
  template <typename Body>
  void SumOverResiduals(int size, const Body& body, Eigen::VectorXd* out) const;
  void MultiplyJ(const Eigen::VectorXd* reduced, const Eigen::VectorXd* eliminated,
                 Eigen::VectorXd* rows) const;
  void MultiplyJtReduced(const Eigen::VectorXd& rows, Eigen::VectorXd* out) const;
  void MultiplyJtEliminated(const Eigen::VectorXd& rows, Eigen::VectorXd* out) const;
  void ComputeGradientAndScaling();
  void ComputeEliminatedGram();  // eliminated_gram_ from the Jacobian
  void FactorEliminated(double mu);
  void SolveEliminated(const Eigen::VectorXd& in, Eigen::VectorXd* out) const;
  void BuildPreconditioner(double mu);
  // The Gram blocks of a residual that provides them (Residual::gram) for its
  // slots in segment `a` (of group g) against every reduced slot of a group
  // ≤ g (the band's lower triangle) or shared (the border).
  void AddGramToPreconditioner(const Residual& r, const Segment& a, int g);
  int EliminatedSlot(const Residual& r) const {
    for (std::size_t k = 0; k < r.slot_block.size(); ++k) {
      if (r.slot_block[k] == r.eliminated) return static_cast<int>(k);
    }
    return -1;
  }
  // Solves L Lᵀ x = x in place with the band factor (x: a vector or a
  // matrix of right-hand sides).
  template <typename Matrix>
  void BandSolve(Matrix* x) const;
  void ApplyPreconditioner(const Eigen::VectorXd& in, Eigen::VectorXd* out) const;
  void ApplyReduced(const Eigen::VectorXd& v, double mu, Eigen::VectorXd* out) const;
  int SolveStep(double mu, Eigen::VectorXd* step_reduced, Eigen::VectorXd* step_eliminated);
  std::vector<double> Save() const;
  void Restore(const std::vector<double>& saved);
  void Step(const std::vector<double>& saved, const Eigen::VectorXd& reduced,
            const Eigen::VectorXd& eliminated);
  double ParameterNorm() const;

  const StructuredSolverOptions& options_;
  ceres::Problem* problem_;
  std::vector<Block> blocks_;
  std::vector<int> group_offset_;  // columns of group g: [g_off[g], g_off[g + 1])
  int num_group_columns_ = 0, num_reduced_ = 0, num_eliminated_ = 0, num_rows_ = 0;
  int band_ = 0;
  std::vector<int> shared_blocks_, eliminated_blocks_;
  std::vector<Residual> residuals_;
  std::vector<std::vector<Ref>> group_refs_, eliminated_refs_;
  std::vector<int> residuals_with_shared_;
  int max_rows_per_residual_ = 0;
  std::vector<double> jacobian_;
  std::vector<double> factors_;  // A of the residuals with a basis_factor, 6 each
  Eigen::VectorXd r_, gradient_reduced_, gradient_eliminated_, d_reduced_, d_eliminated_;
  std::vector<Eigen::LLT<Eigen::MatrixXd>> eliminated_llt_;  // per eliminated block
  std::vector<Eigen::MatrixXd> eliminated_gram_;  // J_pᵀ J_p per eliminated block
  std::vector<std::vector<Eigen::MatrixXd>> blocks_band_;  // [g][d]: block (g, g − d)
  Eigen::MatrixXd border_, border_solved_;
  Eigen::LLT<Eigen::MatrixXd> corner_llt_;
  double evaluate_seconds_ = 0.0, preconditioner_seconds_ = 0.0, cg_seconds_ = 0.0;
};

bool Solver::Setup(const StructuredLayout& layout, std::string* error) {
  std::unordered_map<const double*, int> index;
  auto add = [&](double* values, bool eliminated, int group) {
    if (!problem_->HasParameterBlock(values) || problem_->IsParameterBlockConstant(values) ||
        index.count(values)) {
      return;
    }
    Block b;
    b.values = values;
    b.ambient = problem_->ParameterBlockSize(values);
    b.manifold = problem_->HasManifold(values) ? problem_->GetManifold(values) : nullptr;
    b.size = b.manifold != nullptr ? b.manifold->TangentSize() : b.ambient;
    b.eliminated = eliminated;
    b.group = group;
    int& counter = eliminated ? num_eliminated_ : num_reduced_;
    b.offset = counter;
    counter += b.size;
    index[values] = static_cast<int>(blocks_.size());
    if (eliminated) {
      eliminated_blocks_.push_back(static_cast<int>(blocks_.size()));
    } else if (group < 0) {
      shared_blocks_.push_back(static_cast<int>(blocks_.size()));
    }
    blocks_.push_back(b);
  };
  group_offset_.push_back(0);
  for (std::size_t g = 0; g < layout.groups.size(); ++g) {
    for (double* values : layout.groups[g]) add(values, false, static_cast<int>(g));
    group_offset_.push_back(num_reduced_);
  }
  num_group_columns_ = num_reduced_;
  for (double* values : layout.globals) add(values, false, -1);
  for (double* values : layout.eliminated) add(values, true, -1);
  const int num_groups = static_cast<int>(layout.groups.size());

  std::vector<ceres::ResidualBlockId> ids;
  problem_->GetResidualBlocks(&ids);
  residuals_.reserve(ids.size());
  std::size_t jac = 0, factor = 0;
  for (ceres::ResidualBlockId id : ids) {
    Residual r;
    r.cost = problem_->GetCostFunctionForResidualBlock(id);
    r.loss = problem_->GetLossFunctionForResidualBlock(id);
    const BasisJacobianFactor* basis_factor =
        r.loss == nullptr ? dynamic_cast<const BasisJacobianFactor*>(r.cost) : nullptr;
    r.m = r.cost->num_residuals();
    r.row = num_rows_;
    num_rows_ += r.m;
    problem_->GetParameterBlocksForResidualBlock(id, &r.parameters);
    for (double* values : r.parameters) {
      int block = -1;
      if (!problem_->IsParameterBlockConstant(values)) {
        const auto it = index.find(values);
        if (it == index.end()) {
          *error = "a free parameter block of the problem is not in the layout";
          return false;
        }
        block = it->second;
      }
      r.slot_block.push_back(block);
      r.slot_jcol.push_back(r.width);
      if (block < 0) continue;
      const Block& b = blocks_[block];
      if (b.eliminated) {
        if (r.eliminated >= 0) {
          *error = "a residual block holds two eliminated blocks";
          return false;
        }
        r.eliminated = block;
        r.eliminated_jcol = r.width;
        if (basis_factor != nullptr && b.manifold == nullptr &&
            r.slot_block.size() == BasisJacobianFactor::kBasisSlot + 1) {
          // The basis block's columns are formed from A and l, not stored.
          r.basis_factor = basis_factor;
          r.num_bases = basis_factor->num_bases();
          r.weights = r.parameters[BasisJacobianFactor::kWeightsSlot];
          r.factor = factor;
          factor += 6;
          r.slot_jcol.back() = -1;
          continue;
        }
      } else {
        // Merge with the previous segment when the columns continue it
        // within the same group.
        if (!r.reduced.empty() && b.group >= 0 && r.reduced.back().group == b.group &&
            r.reduced.back().col + r.reduced.back().width == b.offset &&
            r.reduced.back().jcol + r.reduced.back().width == r.width) {
          r.reduced.back().width += b.size;
        } else {
          r.reduced.push_back({b.offset, b.size, r.width, b.group});
        }
      }
      r.width += b.size;
    }
    r.jac = jac;
    jac += static_cast<std::size_t>(r.m) * r.width;
    int lo = num_groups, hi = -1;
    for (const Segment& s : r.reduced) {
      if (s.group < 0) continue;
      lo = std::min(lo, s.group);
      hi = std::max(hi, s.group);
    }
    if (hi >= 0) band_ = std::max(band_, hi - lo);
    if (r.loss == nullptr) {
      r.product = dynamic_cast<const JacobianProduct*>(r.cost);
      for (int block : r.slot_block) {
        if (block >= 0 && blocks_[block].manifold != nullptr) r.product = nullptr;
      }
    }
    if (r.product != nullptr && r.product->ProvidesGram()) {
      r.gram = true;
      jac -= static_cast<std::size_t>(r.m) * r.width;  // nothing stored
    }
    residuals_.push_back(std::move(r));
  }
  jacobian_.assign(jac, 0.0);
  factors_.assign(factor, 0.0);
  r_.setZero(num_rows_);

  group_refs_.assign(num_groups, {});
  eliminated_refs_.assign(eliminated_blocks_.size(), {});
  std::vector<int> eliminated_position(blocks_.size(), -1);
  for (std::size_t k = 0; k < eliminated_blocks_.size(); ++k) {
    eliminated_position[eliminated_blocks_[k]] = k;
  }
  for (std::size_t i = 0; i < residuals_.size(); ++i) {
    const Residual& r = residuals_[i];
    bool with_shared = false;
    for (std::size_t s = 0; s < r.reduced.size(); ++s) {
      if (r.reduced[s].group >= 0) {
        group_refs_[r.reduced[s].group].push_back({static_cast<int>(i), static_cast<int>(s)});
      } else {
        with_shared = true;
      }
    }
    if (with_shared) residuals_with_shared_.push_back(static_cast<int>(i));
    if (r.eliminated >= 0) {
      eliminated_refs_[eliminated_position[r.eliminated]].push_back({static_cast<int>(i), -1});
    }
    max_rows_per_residual_ = std::max(max_rows_per_residual_, r.m);
  }
  return true;
}

bool Solver::Evaluate(bool with_jacobian, double* cost) {
  const Clock::time_point start = Clock::now();
  const int n = static_cast<int>(residuals_.size());
  std::vector<double> partial(kReductionPieces, 0.0);
  std::vector<char> ok(kReductionPieces, 1);
  ParallelForPieces(n, kReductionPieces, options_.solver.num_threads, kGrain,
                    [&](int begin, int end, int worker) {
    std::vector<std::vector<double>> ambient;
    std::vector<double*> jacobians;
    double sum = 0.0;
    for (int i = begin; i < end; ++i) {
      Residual& r = residuals_[i];
      double* residual = r_.data() + r.row;
      jacobians.assign(r.parameters.size(), nullptr);
      if (ambient.size() < r.parameters.size()) ambient.resize(r.parameters.size());
      const bool store = with_jacobian && !r.gram;
      if (store) {
        for (std::size_t k = 0; k < r.parameters.size(); ++k) {
          if (r.slot_block[k] < 0 || r.slot_jcol[k] < 0) continue;
          ambient[k].resize(static_cast<std::size_t>(r.m) * blocks_[r.slot_block[k]].ambient);
          jacobians[k] = ambient[k].data();
        }
      }
      const bool evaluated =
          r.basis_factor != nullptr && store
              ? r.basis_factor->EvaluateWithBasisFactor(r.parameters.data(), residual,
                                                        jacobians.data(),
                                                        factors_.data() + r.factor)
              : r.cost->Evaluate(r.parameters.data(), residual,
                                 store ? jacobians.data() : nullptr);
      if (!evaluated) {
        ok[worker] = 0;
        return;
      }
      if (store) {
        for (std::size_t k = 0; k < r.parameters.size(); ++k) {
          if (r.slot_block[k] < 0 || r.slot_jcol[k] < 0) continue;
          const Block& b = blocks_[r.slot_block[k]];
          RowMap out(J(r) + r.slot_jcol[k], r.m, b.size, Eigen::OuterStride<>(r.width));
          const Eigen::Map<const RowMatrix> in(ambient[k].data(), r.m, b.ambient);
          if (b.manifold == nullptr) {
            out = in;
          } else {
            RowMatrix plus(b.ambient, b.size);
            b.manifold->PlusJacobian(b.values, plus.data());
            out.noalias() = in * plus;
          }
        }
      }
      double squared = 0.0;
      for (int j = 0; j < r.m; ++j) squared += residual[j] * residual[j];
      if (r.loss == nullptr) {
        sum += 0.5 * squared;
        continue;
      }
      // Ceres' correction of residuals and Jacobians for a robust loss (Triggs
      // et al.), so that JᵀJ and Jᵀr are its Gauss–Newton model.
      double rho[3];
      r.loss->Evaluate(squared, rho);
      sum += 0.5 * rho[0];
      const double sqrt_rho1 = std::sqrt(rho[1]);
      double scaling = sqrt_rho1, alpha_sq_norm = 0.0;
      if (squared > 0.0 && rho[2] > 0.0) {
        const double alpha = 1.0 - std::sqrt(1.0 + 2.0 * squared * rho[2] / rho[1]);
        scaling = sqrt_rho1 / (1.0 - alpha);
        alpha_sq_norm = alpha / squared;
      }
      if (with_jacobian) {
        Eigen::Map<RowMatrix> j(J(r), r.m, r.width);
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
  evaluate_seconds_ += SecondsSince(start);
  if (std::find(ok.begin(), ok.end(), 0) != ok.end()) return false;
  *cost = 0.0;
  for (double p : partial) *cost += p;
  return std::isfinite(*cost);
}

void Solver::AddResidualJx(const Residual& r, const double* reduced, const double* eliminated,
                           double* y) const {
  if (r.product != nullptr) {
    SlotPointers x(r.parameters.size());
    for (std::size_t k = 0; k < r.parameters.size(); ++k) {
      const int block = r.slot_block[k];
      if (block < 0) continue;
      const Block& b = blocks_[block];
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
    const Block& b = blocks_[r.eliminated];
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
      AddAx(factors_.data() + r.factor, 2, 3, 3, u, y);
      return;
    }
    AddAx(J(r) + r.eliminated_jcol, r.m, b.size, r.width, eliminated + b.offset, y);
  }
}

void Solver::AddResidualJty(const Residual& r, const double* y, double* reduced,
                            double* eliminated) const {
  if (r.product != nullptr) {
    SlotPointers out(r.parameters.size());
    bool any = false;
    for (std::size_t k = 0; k < r.parameters.size(); ++k) {
      const int block = r.slot_block[k];
      if (block < 0) continue;
      const Block& b = blocks_[block];
      double* target = b.eliminated ? eliminated : reduced;
      if (target != nullptr) {
        out[k] = target + b.offset;
        any = true;
      }
    }
    if (any) r.product->AddJacobianTransposeProduct(r.parameters.data(), y, out.data());
    return;
  }
  if (reduced != nullptr) {
    for (const Segment& s : r.reduced) {
      AddAty(J(r) + s.jcol, r.m, s.width, r.width, y, reduced + s.col);
    }
  }
  if (eliminated != nullptr && r.eliminated >= 0) {
    const Block& b = blocks_[r.eliminated];
    if (r.basis_factor != nullptr) {
      // [l_k Aᵀ y]_k.
      double v[3] = {0.0, 0.0, 0.0};
      AddAty(factors_.data() + r.factor, 2, 3, 3, y, v);
      double* out = eliminated + b.offset;
      for (int k = 0; k < r.num_bases; ++k) {
        const double l = r.weights[k];
        out[3 * k] += l * v[0];
        out[3 * k + 1] += l * v[1];
        out[3 * k + 2] += l * v[2];
      }
      return;
    }
    AddAty(J(r) + r.eliminated_jcol, r.m, b.size, r.width, y, eliminated + b.offset);
  }
}

template <typename Body>
void Solver::SumOverResiduals(int size, const Body& body, Eigen::VectorXd* out) const {
  std::vector<Eigen::VectorXd> sums(kReductionPieces);
  const int pieces = ParallelForPieces(
      static_cast<int>(residuals_.size()), kReductionPieces, options_.solver.num_threads, kGrain,
      [&](int begin, int end, int piece) {
        Eigen::VectorXd& sum = sums[piece];
        sum.setZero(size);
        for (int i = begin; i < end; ++i) body(i, sum.data());
      });
  *out = std::move(sums[0]);
  for (int w = 1; w < pieces; ++w) {
    if (sums[w].size() == size) *out += sums[w];
  }
}

void Solver::MultiplyJ(const Eigen::VectorXd* reduced, const Eigen::VectorXd* eliminated,
                       Eigen::VectorXd* rows) const {
  rows->resize(num_rows_);
  ParallelFor(static_cast<int>(residuals_.size()), options_.solver.num_threads, kGrain,
              [&](int begin, int end) {
                for (int i = begin; i < end; ++i) {
                  const Residual& r = residuals_[i];
                  double* out = rows->data() + r.row;
                  std::fill(out, out + r.m, 0.0);
                  AddResidualJx(r, reduced != nullptr ? reduced->data() : nullptr,
                                eliminated != nullptr ? eliminated->data() : nullptr, out);
                }
              });
}

void Solver::MultiplyJtReduced(const Eigen::VectorXd& rows, Eigen::VectorXd* out) const {
  SumOverResiduals(num_reduced_, [&](int i, double* sum) {
    const Residual& r = residuals_[i];
    AddResidualJty(r, rows.data() + r.row, sum, nullptr);
  }, out);
}

void Solver::MultiplyJtEliminated(const Eigen::VectorXd& rows, Eigen::VectorXd* out) const {
  SumOverResiduals(num_eliminated_, [&](int i, double* sum) {
    const Residual& r = residuals_[i];
    AddResidualJty(r, rows.data() + r.row, nullptr, sum);
  }, out);
}

void Solver::ComputeEliminatedGram() {
  eliminated_gram_.resize(eliminated_blocks_.size());
  ParallelFor(static_cast<int>(eliminated_blocks_.size()), options_.solver.num_threads,
              kEliminatedGrain, [&](int begin, int end) {
                RowMatrix stacked;
                for (int k = begin; k < end; ++k) {
                  const Block& b = blocks_[eliminated_blocks_[k]];
                  // Residuals with a basis factor add (l lᵀ) ⊗ (Aᵀ A)
                  // directly (lower triangle).
                  Eigen::MatrixXd& c = eliminated_gram_[k];
                  c.setZero(b.size, b.size);
                  int rows = 0;
                  for (const Ref& ref : eliminated_refs_[k]) {
                    const Residual& r = residuals_[ref.residual];
                    if (r.gram) {
                      const int slot = EliminatedSlot(r);
                      r.product->AddGram(r.parameters.data(), slot, slot, c.data(),
                                         static_cast<int>(c.rows()));
                      continue;
                    }
                    if (r.basis_factor == nullptr) {
                      rows += r.m;
                      continue;
                    }
                    const double* a = factors_.data() + r.factor;
                    double ata[9];
                    for (int i = 0; i < 3; ++i) {
                      for (int j = 0; j < 3; ++j) ata[3 * i + j] = a[i] * a[j] + a[3 + i] * a[3 + j];
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
                    for (const Ref& ref : eliminated_refs_[k]) {
                      const Residual& r = residuals_[ref.residual];
                      if (r.basis_factor != nullptr || r.gram) continue;
                      stacked.middleRows(rows, r.m) = Cols(r, r.eliminated_jcol, b.size);
                      rows += r.m;
                    }
                    c.selfadjointView<Eigen::Lower>().rankUpdate(stacked.transpose());
                  }
                  c.triangularView<Eigen::StrictlyUpper>() = c.transpose();
                }
              });
}

void Solver::ComputeGradientAndScaling() {
  ComputeEliminatedGram();
  MultiplyJtReduced(r_, &gradient_reduced_);
  MultiplyJtEliminated(r_, &gradient_eliminated_);
  // diag(JᵀJ): the column sums of squares.
  d_reduced_.setZero(num_reduced_);
  d_eliminated_.setZero(num_eliminated_);
  for (const Residual& r : residuals_) {
    if (r.gram) {
      for (std::size_t k = 0; k < r.parameters.size(); ++k) {
        if (r.slot_block[k] < 0) continue;
        const Block& b = blocks_[r.slot_block[k]];
        double* d = (b.eliminated ? d_eliminated_ : d_reduced_).data() + b.offset;
        r.product->AddGramDiagonal(r.parameters.data(), static_cast<int>(k), d);
      }
      continue;
    }
    for (const Segment& s : r.reduced) {
      d_reduced_.segment(s.col, s.width) += Cols(r, s.jcol, s.width).colwise().squaredNorm().transpose();
    }
    if (r.eliminated >= 0) {
      const Block& b = blocks_[r.eliminated];
      if (r.basis_factor != nullptr) {
        // Column (k, i) of l_k A: l_k² Σ_rows A(row, i)².
        const double* a = factors_.data() + r.factor;
        for (int k = 0; k < r.num_bases; ++k) {
          const double l2 = r.weights[k] * r.weights[k];
          for (int i = 0; i < 3; ++i) {
            d_eliminated_[b.offset + 3 * k + i] += l2 * (a[i] * a[i] + a[3 + i] * a[3 + i]);
          }
        }
        continue;
      }
      d_eliminated_.segment(b.offset, b.size) +=
          Cols(r, r.eliminated_jcol, b.size).colwise().squaredNorm().transpose();
    }
  }
  d_reduced_ = d_reduced_.cwiseMax(1e-6).cwiseMin(1e32);
  d_eliminated_ = d_eliminated_.cwiseMax(1e-6).cwiseMin(1e32);
}

void Solver::FactorEliminated(double mu) {
  eliminated_llt_.resize(eliminated_blocks_.size());
  ParallelFor(static_cast<int>(eliminated_blocks_.size()), options_.solver.num_threads, kEliminatedGrain,
              [&](int begin, int end) {
                for (int k = begin; k < end; ++k) {
                  const Block& b = blocks_[eliminated_blocks_[k]];
                  Eigen::MatrixXd c = eliminated_gram_[k];
                  c.diagonal() += mu * d_eliminated_.segment(b.offset, b.size);
                  eliminated_llt_[k].compute(c);
                }
              });
}

void Solver::SolveEliminated(const Eigen::VectorXd& in, Eigen::VectorXd* out) const {
  out->resize(num_eliminated_);
  for (std::size_t k = 0; k < eliminated_blocks_.size(); ++k) {
    const Block& b = blocks_[eliminated_blocks_[k]];
    out->segment(b.offset, b.size) = eliminated_llt_[k].solve(in.segment(b.offset, b.size));
  }
}

void Solver::BuildPreconditioner(double mu) {
  const Clock::time_point start = Clock::now();
  const int num_groups = static_cast<int>(group_refs_.size());
  const int num_shared = num_reduced_ - num_group_columns_;
  blocks_band_.assign(num_groups, std::vector<Eigen::MatrixXd>(band_ + 1));
  border_ = Eigen::MatrixXd::Zero(num_group_columns_, num_shared);
  ParallelFor(num_groups, options_.solver.num_threads, kGroupGrain, [&](int begin, int end) {
    for (int g = begin; g < end; ++g) {
      for (int d = 0; d <= band_ && g - d >= 0; ++d) {
        blocks_band_[g][d] = Eigen::MatrixXd::Zero(GroupSize(g), GroupSize(g - d));
      }
      for (const Ref& ref : group_refs_[g]) {
        const Residual& r = residuals_[ref.residual];
        const Segment& a = r.reduced[ref.segment];
        if (r.gram) {
          AddGramToPreconditioner(r, a, g);
          continue;
        }
        const int row_a = a.col - group_offset_[g];
        for (const Segment& b : r.reduced) {
          if (b.group < 0) {
            AddAtB(J(r) + a.jcol, r.m, a.width, r.width, J(r) + b.jcol, b.width, r.width,
                   &border_(a.col, b.col - num_group_columns_), border_.rows());
            continue;
          }
          const int d = g - b.group;
          if (d < 0) continue;  // the lower triangle of the band only
          Eigen::MatrixXd& block = blocks_band_[g][d];
          AddAtB(J(r) + a.jcol, r.m, a.width, r.width, J(r) + b.jcol, b.width, r.width,
                 &block(row_a, b.col - group_offset_[b.group]), block.rows());
        }
      }
      blocks_band_[g][0].diagonal() += mu * d_reduced_.segment(group_offset_[g], GroupSize(g));
    }
  });
  Eigen::MatrixXd corner = Eigen::MatrixXd::Zero(num_shared, num_shared);
  for (int i : residuals_with_shared_) {
    const Residual& r = residuals_[i];
    if (r.gram) {
      // The corner's column of slot k's block, or -1 when it is not shared.
      const auto corner_column = [&](std::size_t k) {
        const int block = r.slot_block[k];
        if (block < 0 || blocks_[block].eliminated || blocks_[block].group >= 0) return -1;
        return blocks_[block].offset - num_group_columns_;
      };
      for (std::size_t ka = 0; ka < r.parameters.size(); ++ka) {
        const int ia = corner_column(ka);
        if (ia < 0) continue;
        for (std::size_t kb = 0; kb < r.parameters.size(); ++kb) {
          const int ib = corner_column(kb);
          if (ib < 0) continue;
          r.product->AddGram(r.parameters.data(), static_cast<int>(ka), static_cast<int>(kb),
                             &corner(ia, ib), static_cast<int>(corner.rows()));
        }
      }
      continue;
    }
    for (const Segment& a : r.reduced) {
      if (a.group >= 0) continue;
      for (const Segment& b : r.reduced) {
        if (b.group >= 0) continue;
        corner.block(a.col - num_group_columns_, b.col - num_group_columns_, a.width, b.width)
            .noalias() += Cols(r, a.jcol, a.width).transpose() * Cols(r, b.jcol, b.width);
      }
    }
  }
  corner.diagonal() += mu * d_reduced_.tail(num_shared);
  // Block-band Cholesky: blocks_band_[g][d] ← L(g, g − d).
  for (int g = 0; g < num_groups; ++g) {
    for (int d = std::min(band_, g); d >= 1; --d) {
      Eigen::MatrixXd m = blocks_band_[g][d];
      for (int e = d + 1; e <= band_ && g - e >= 0; ++e) {
        m.noalias() -= blocks_band_[g][e] * blocks_band_[g - d][e - d].transpose();
      }
      blocks_band_[g][d] = blocks_band_[g - d][0].triangularView<Eigen::Lower>().solve(m.transpose()).transpose();
    }
    Eigen::MatrixXd m = blocks_band_[g][0];
    for (int d = 1; d <= band_ && g - d >= 0; ++d) m.noalias() -= blocks_band_[g][d] * blocks_band_[g][d].transpose();
    Eigen::LLT<Eigen::MatrixXd> llt(m);
    if (llt.info() != Eigen::Success) {
      // A preconditioner only needs to be positive definite.
      m.diagonal().array() += 1e-10 * m.diagonal().cwiseAbs().maxCoeff() + 1e-300;
      llt.compute(m);
    }
    blocks_band_[g][0] = llt.matrixL();
  }
  if (num_shared > 0) {
    border_solved_ = border_;
    BandSolve(&border_solved_);
    corner_llt_.compute(corner - border_.transpose() * border_solved_);
  }
  preconditioner_seconds_ += SecondsSince(start);
}

void Solver::AddGramToPreconditioner(const Residual& r, const Segment& a, int g) {
  for (std::size_t ka = 0; ka < r.parameters.size(); ++ka) {
    if (r.slot_block[ka] < 0) continue;
    const Block& ba = blocks_[r.slot_block[ka]];
    if (ba.eliminated || ba.offset < a.col || ba.offset >= a.col + a.width) continue;
    const int row_a = ba.offset - group_offset_[g];
    for (std::size_t kb = 0; kb < r.parameters.size(); ++kb) {
      if (r.slot_block[kb] < 0) continue;
      const Block& bb = blocks_[r.slot_block[kb]];
      if (bb.eliminated) continue;
      if (bb.group < 0) {
        r.product->AddGram(r.parameters.data(), static_cast<int>(ka), static_cast<int>(kb),
                           &border_(ba.offset, bb.offset - num_group_columns_),
                           static_cast<int>(border_.rows()));
        continue;
      }
      const int d = g - bb.group;
      if (d < 0) continue;  // the lower triangle of the band only
      Eigen::MatrixXd& block = blocks_band_[g][d];
      r.product->AddGram(r.parameters.data(), static_cast<int>(ka), static_cast<int>(kb),
                         &block(row_a, bb.offset - group_offset_[bb.group]),
                         static_cast<int>(block.rows()));
    }
  }
}

template <typename Matrix>
void Solver::BandSolve(Matrix* x) const {
  const int num_groups = static_cast<int>(group_refs_.size());
  for (int g = 0; g < num_groups; ++g) {
    auto xg = x->middleRows(group_offset_[g], GroupSize(g));
    for (int d = 1; d <= band_ && g - d >= 0; ++d) {
      xg.noalias() -= blocks_band_[g][d] * x->middleRows(group_offset_[g - d], GroupSize(g - d));
    }
    blocks_band_[g][0].triangularView<Eigen::Lower>().solveInPlace(xg);
  }
  for (int g = num_groups - 1; g >= 0; --g) {
    auto xg = x->middleRows(group_offset_[g], GroupSize(g));
    for (int d = 1; d <= band_ && g + d < num_groups; ++d) {
      xg.noalias() -= blocks_band_[g + d][d].transpose() * x->middleRows(group_offset_[g + d], GroupSize(g + d));
    }
    blocks_band_[g][0].transpose().triangularView<Eigen::Upper>().solveInPlace(xg);
  }
}

void Solver::ApplyPreconditioner(const Eigen::VectorXd& in, Eigen::VectorXd* out) const {
  const int num_shared = num_reduced_ - num_group_columns_;
  Eigen::VectorXd x = in.head(num_group_columns_);
  BandSolve(&x);
  out->resize(num_reduced_);
  if (num_shared == 0) {
    *out = x;
    return;
  }
  // [A B; Bᵀ C]: y = (C − Bᵀ A⁻¹ B)⁻¹ (b − Bᵀ A⁻¹ a), x = A⁻¹ a − A⁻¹ B y.
  const Eigen::VectorXd y = corner_llt_.solve(in.tail(num_shared) - border_.transpose() * x);
  out->head(num_group_columns_) = x.col(0) - border_solved_ * y;
  out->tail(num_shared) = y;
}

void Solver::ApplyReduced(const Eigen::VectorXd& v, double mu, Eigen::VectorXd* out) const {
  // S v = J_fᵀ (J_f v − J_p C̃⁻¹ J_pᵀ J_f v) + μ D_f v, in two passes over the
  // residual blocks in the order their Jacobians are stored (they do not fit
  // in the caches, so reading them is the cost): rows = J_f v and J_pᵀ rows;
  // then J_fᵀ (rows − J_p C̃⁻¹ J_pᵀ rows).
  Eigen::VectorXd rows(num_rows_), projected, solved;
  SumOverResiduals(num_eliminated_, [&](int i, double* sum) {
    const Residual& r = residuals_[i];
    double* y = rows.data() + r.row;
    std::fill(y, y + r.m, 0.0);
    AddResidualJx(r, v.data(), nullptr, y);
    if (r.eliminated >= 0) AddResidualJty(r, y, nullptr, sum);
  }, &projected);
  SolveEliminated(projected, &solved);
  SumOverResiduals(num_reduced_, [&](int i, double* sum) {
    const Residual& r = residuals_[i];
    double* y = rows.data() + r.row;  // each residual's own rows: no race
    if (r.eliminated >= 0) {
      double correction[8] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
      std::vector<double> heap;
      double* c = correction;
      if (r.m > 8) {
        heap.assign(r.m, 0.0);
        c = heap.data();
      }
      AddResidualJx(r, nullptr, solved.data(), c);
      for (int a = 0; a < r.m; ++a) y[a] -= c[a];
    }
    AddResidualJty(r, y, sum, nullptr);
  }, out);
  out->array() += mu * d_reduced_.array() * v.array();
}

int Solver::SolveStep(double mu, Eigen::VectorXd* step_reduced, Eigen::VectorXd* step_eliminated) {
  FactorEliminated(mu);
  BuildPreconditioner(mu);
  const Clock::time_point start = Clock::now();
  // Right-hand side of the reduced system: −g_f + J_fᵀ J_p C̃⁻¹ g_p.
  Eigen::VectorXd solved, rows, rhs;
  SolveEliminated(gradient_eliminated_, &solved);
  MultiplyJ(nullptr, &solved, &rows);
  MultiplyJtReduced(rows, &rhs);
  rhs -= gradient_reduced_;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(num_reduced_), residual = rhs, z, p, q;
  ApplyPreconditioner(residual, &z);
  p = z;
  double rz = residual.dot(z);
  const double target = options_.cg_relative_tolerance * rhs.norm();
  int iterations = 0;
  while (iterations < options_.max_cg_iterations && residual.norm() > target) {
    ApplyReduced(p, mu, &q);
    const double pq = p.dot(q);
    if (!(pq > 0.0)) break;
    const double alpha = rz / pq;
    x += alpha * p;
    residual -= alpha * q;
    ApplyPreconditioner(residual, &z);
    const double rz_next = residual.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
    ++iterations;
  }
  *step_reduced = x;
  // Back-substitution: δ_p = C̃⁻¹ (−g_p − J_pᵀ J_f δ_f).
  Eigen::VectorXd jx, projected;
  MultiplyJ(&x, nullptr, &jx);
  MultiplyJtEliminated(jx, &projected);
  SolveEliminated(-gradient_eliminated_ - projected, step_eliminated);
  cg_seconds_ += SecondsSince(start);
  return iterations;
}

std::vector<double> Solver::Save() const {
  std::vector<double> saved;
  for (const Block& b : blocks_) saved.insert(saved.end(), b.values, b.values + b.ambient);
  return saved;
}

void Solver::Restore(const std::vector<double>& saved) {
  std::size_t k = 0;
  for (Block& b : blocks_) {
    std::copy(saved.begin() + k, saved.begin() + k + b.ambient, b.values);
    k += b.ambient;
  }
}

void Solver::Step(const std::vector<double>& saved, const Eigen::VectorXd& reduced,
                  const Eigen::VectorXd& eliminated) {
  std::size_t k = 0;
  for (Block& b : blocks_) {
    const double* delta = (b.eliminated ? eliminated : reduced).data() + b.offset;
    if (b.manifold != nullptr) {
      b.manifold->Plus(saved.data() + k, delta, b.values);
    } else {
      for (int i = 0; i < b.ambient; ++i) b.values[i] = saved[k + i] + delta[i];
    }
    k += b.ambient;
  }
}

double Solver::ParameterNorm() const {
  double sum = 0.0;
  for (const Block& b : blocks_) {
    sum += Eigen::Map<const Eigen::VectorXd>(b.values, b.ambient).squaredNorm();
  }
  return std::sqrt(sum);
}

bool Solver::Run(StructuredSolverSummary* summary) {
  const Clock::time_point start = Clock::now();
  double cost = 0.0;
  if (!Evaluate(true, &cost)) {
    summary->message = "the cost is not finite at the start";
    return true;
  }
  summary->initial_cost = cost;
  if (options_.solver.progress) options_.solver.progress(IterationReport{0, cost, SecondsSince(start)});
  ComputeGradientAndScaling();
  double radius = options_.solver.initial_trust_region_radius, decrease = 2.0;
  int iteration = 0;
  summary->message = "iteration limit";
  Eigen::VectorXd step_reduced, step_eliminated, j_step;
  while (true) {
    const double gradient_max =
        std::max(gradient_reduced_.size() ? gradient_reduced_.cwiseAbs().maxCoeff() : 0.0,
                 gradient_eliminated_.size() ? gradient_eliminated_.cwiseAbs().maxCoeff() : 0.0);
    if (gradient_max <= options_.solver.gradient_tolerance) {
      summary->message = "gradient tolerance";
      summary->converged = true;
      break;
    }
    if (iteration >= options_.solver.max_iterations) break;
    if (options_.solver.max_seconds > 0.0 && SecondsSince(start) >= options_.solver.max_seconds) {
      summary->message = "time limit";
      break;
    }
    if (options_.solver.stop_requested && options_.solver.stop_requested()) {
      summary->message = "stopped on request";
      summary->stopped = true;
      break;
    }
    ++iteration;
    const double mu = 1.0 / radius;
    summary->cg_iterations += SolveStep(mu, &step_reduced, &step_eliminated);
    MultiplyJ(&step_reduced, &step_eliminated, &j_step);
    // The decrease the linear model predicts: cost − ½||r + J δ||².
    const double model_decrease = -(j_step.dot(r_) + 0.5 * j_step.squaredNorm());
    const std::vector<double> saved = Save();
    const double step_norm = std::sqrt(step_reduced.squaredNorm() + step_eliminated.squaredNorm());
    if (step_norm <= options_.solver.parameter_tolerance *
                         (ParameterNorm() + options_.solver.parameter_tolerance)) {
      summary->message = "parameter tolerance";
      summary->converged = true;
      break;
    }
    Step(saved, step_reduced, step_eliminated);
    const Eigen::VectorXd saved_r = r_;
    double new_cost = 0.0;
    const bool finite = Evaluate(false, &new_cost);
    const double ratio = finite && model_decrease > 0.0 ? (cost - new_cost) / model_decrease : -1.0;
    VLOG(3) << "structured LM " << iteration << ": cost " << cost << " -> " << new_cost
            << " ratio " << ratio << " radius " << radius << " step " << step_norm;
    if (ratio > 1e-3) {
      const double change = cost - new_cost;
      cost = new_cost;
      radius = std::min(1e16, radius / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * ratio - 1.0, 3)));
      decrease = 2.0;
      Evaluate(true, &new_cost);
      ComputeGradientAndScaling();
      if (options_.solver.progress) options_.solver.progress(IterationReport{iteration, cost, SecondsSince(start)});
      if (change <= options_.solver.function_tolerance * cost) {
        summary->message = "function tolerance";
        summary->converged = true;
        break;
      }
    } else {
      Restore(saved);
      r_ = saved_r;
      radius /= decrease;
      decrease *= 2.0;
      if (options_.solver.progress) options_.solver.progress(IterationReport{iteration, cost, SecondsSince(start)});
      if (radius < 1e-32) {
        summary->message = "trust region below 1e-32";
        break;
      }
    }
  }
  summary->usable = std::isfinite(cost);
  summary->iterations = iteration;
  summary->final_cost = cost;
  summary->evaluate_seconds = evaluate_seconds_;
  summary->preconditioner_seconds = preconditioner_seconds_;
  summary->cg_seconds = cg_seconds_;
  summary->total_seconds = SecondsSince(start);
  return true;
}

}  // namespace

bool SolveStructured(const StructuredSolverOptions& options, const StructuredLayout& layout,
                     ceres::Problem* problem, StructuredSolverSummary* summary,
                     std::string* error) {
  *summary = StructuredSolverSummary();
  Solver solver(options, problem);
  if (!solver.Setup(layout, error)) return false;
  return solver.Run(summary);
}

}  // namespace nrsfm
