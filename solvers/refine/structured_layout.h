// The structured solver's view of a ceres::Problem
// (solvers/refine/structured_solver.h): its free parameter blocks as columns
// and its residual blocks as rows.
//
// Columns are tangent-space coordinates (a block with a manifold has
// Manifold::TangentSize() columns). The reduced side holds one group of
// columns per frame, in time order, then the shared blocks (the dense
// border); the eliminated side holds the point blocks. A block's columns are
// [offset, offset + size) of the reduced or of the eliminated vector. A
// residual block's rows are [row, row + m) of the residual vector; its
// Jacobian, when stored (solvers/refine/structured_jacobian.h), is m × width,
// row-major, its free slots' columns in parameter order (constant blocks
// have none). Blocks are named by their index in StructuredBlocks::blocks.
//
// Assumes the problem is not changed while the blocks are in use (the
// pointers to cost functions, losses, manifolds and values are the
// problem's).
#ifndef NRSFM_SOLVERS_REFINE_STRUCTURED_LAYOUT_H_
#define NRSFM_SOLVERS_REFINE_STRUCTURED_LAYOUT_H_

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "problems/jacobian_product.h"
#include "problems/reprojection_cost_function.h"
#include "solvers/refine/structured_solver.h"

namespace nrsfm {
namespace structured {

using RowMatrix =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// n contiguous items of one of StructuredBlocks' pools (a residual's lists:
// one allocation for all residuals instead of several per residual).
template <typename T>
class Span {
 public:
  Span() = default;
  Span(T* data, std::size_t size) : data_(data), size_(size) {}
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  T* data() const { return data_; }
  T* begin() const { return data_; }
  T* end() const { return data_ + size_; }
  T& operator[](std::size_t i) const { return data_[i]; }
  T& back() const { return data_[size_ - 1]; }

 private:
  T* data_ = nullptr;
  std::size_t size_ = 0;
};

struct Block {
  double* values = nullptr;
  int ambient = 0;  // values in memory
  int size = 0;     // tangent size: columns of the Jacobian
  const ceres::Manifold* manifold = nullptr;
  bool eliminated = false;
  int group = -1;  // frame group of a reduced block, -1 for a shared one
  int offset = 0;  // in the reduced or the eliminated vector
};

// Columns [col, col + width) of a residual block's Jacobian, which sit at
// [jcol, jcol + width) of its stored row-major m × width_total matrix.
struct Segment {
  int col = 0;
  int width = 0;
  int jcol = 0;
  int group = -1;  // -1: shared block
};

// An eliminated block of a residual that holds several (Residual::coupled).
struct Coupled {
  int block = -1;  // Block index
  int jcol = 0;    // first column in the stored Jacobian
};

struct Residual {
  const ceres::CostFunction* cost = nullptr;
  const ceres::LossFunction* loss = nullptr;
  int m = 0;      // residuals
  int row = 0;    // first row in r
  int width = 0;  // columns of the stored Jacobian
  Span<double*> parameters;
  Span<int> slot_block;   // Block index per parameter, -1 = constant
  Span<int> slot_jcol;    // column of the slot in the stored Jacobian
  Span<Segment> reduced;  // merged per group
  int eliminated = -1;    // Block index, -1 = none
  int eliminated_jcol = 0;
  // A residual block that holds two or more eliminated blocks (a term that
  // couples points, e.g. the Delaunay smoothness of the shapes): those
  // blocks and their columns in its stored Jacobian, in parameter order;
  // `eliminated` is then -1. Its J_pᵀJ_p couples the blocks
  // (solvers/refine/schur_elimination.h).
  Span<Coupled> coupled;
  // Products with its Jacobian from its parameters
  // (problems/jacobian_product.h), used in the conjugate gradients instead of
  // the stored Jacobian.
  const JacobianProduct* product = nullptr;
  // A reprojection residual without a robust loss whose eliminated block is
  // its basis block: that block's Jacobian l_k · A is not stored, only A
  // (2 × 3, after its stored Jacobian), and l is read from the weights
  // block (problems/reprojection_cost_function.h, BasisJacobianFactor).
  const BasisJacobianFactor* basis_factor = nullptr;
  const double* weights = nullptr;
  int num_bases = 0;
  // The product also provides its Gram blocks (JacobianProduct::ProvidesGram):
  // no Jacobian is stored for this residual at all.
  bool gram = false;
  // A residual of one of StructuredBlocks::grids: the two Schur-complement
  // passes of the conjugate gradients, C̃'s blocks and the preconditioner
  // leave it out (it is in no group_refs or eliminated_refs), and
  // SchurElimination adds the grid's part at once.
  bool in_grid = false;

  // The parameter slot of the eliminated block, -1 when there is none.
  int EliminatedSlot() const {
    for (std::size_t k = 0; k < slot_block.size(); ++k) {
      if (slot_block[k] == eliminated) return static_cast<int>(k);
    }
    return -1;
  }
};

// The residual blocks of one term with a bilinear form
// (problems/jacobian_product.h: r = s D λ) when they form a full grid: one
// block for every row q and every column e, each once, with
//   λ_q = m ⊙ Σ_j σ_j l_j   (a row: signed weights blocks, reduced, in
//                            frame groups; m the term's mask),
//   D_e = Σ_i τ_i B_i   (a column: signed basis blocks, eliminated),
// and the scale s_e of its column. The Delaunay smoothness is one (rows l_t,
// columns b_i − Σ_j w_ij b_j: the stencils, each with its own points and
// signs), the temporal shape prior another (rows
// l_t − l_(t−1), columns b_p), the deformation prior a third (rows l_t with
// m = (0, 1, …, 1), columns b_p). Their part of a product with the Schur
// complement, of C̃ and of the preconditioner then needs O((E + Q) K²)
// operations instead of O(E Q K) (solvers/refine/schur_elimination.h).
struct BilinearGrid {
  struct Term {
    int block = -1;     // Block index
    double sign = 0.0;  // σ_j or τ_i
  };
  struct Column {
    std::vector<Term> points;
    double scale = 0.0;  // s_e
  };
  std::vector<std::vector<Term>> rows;
  std::vector<Column> columns;
  int num_bases = 0;
  Eigen::VectorXd mask;  // m, K values
};

// A reference from a target (group, shared block or eliminated block) to the
// residual segments that touch it.
struct Ref {
  int residual;
  int segment;  // index into Residual::reduced, or -1 for the eliminated part
};

// Move-only: the residuals' spans point into its pools.
struct StructuredBlocks {
  StructuredBlocks() = default;
  StructuredBlocks(StructuredBlocks&&) = default;
  StructuredBlocks& operator=(StructuredBlocks&&) = default;
  StructuredBlocks(const StructuredBlocks&) = delete;
  StructuredBlocks& operator=(const StructuredBlocks&) = delete;

  std::vector<Block> blocks;
  std::vector<int>
      group_offset;  // columns of group g: [g_off[g], g_off[g + 1])
  int num_group_columns = 0, num_reduced = 0, num_eliminated = 0, num_rows = 0;
  // Largest distance between two groups whose blocks one residual block holds.
  int band = 0;
  std::vector<int> eliminated_blocks;  // Block indices, in the layout's order
  std::vector<Residual> residuals;     // in the problem's order
  // Per group, per eliminated block: the residual segments that touch it
  // (the grids' residuals left out, as in the two lists below).
  std::vector<std::vector<Ref>> group_refs, eliminated_refs;
  std::vector<int> residuals_with_shared;  // residuals that hold a shared block
  std::vector<int> coupling_residuals;     // residuals with `coupled` blocks
  std::vector<BilinearGrid> grids;         // the terms whose residuals form one
  std::vector<int> not_in_grid;  // the other residuals (when there are grids)
  // The residuals' lists (Residual::parameters, …), residual after residual:
  // slot_pool holds a residual's slot_block then its slot_jcol.
  std::vector<double*> parameter_pool;
  std::vector<int> slot_pool;
  std::vector<Segment> segment_pool;
  std::vector<Coupled> coupled_pool;

  int num_groups() const { return static_cast<int>(group_refs.size()); }
  int num_shared() const { return num_reduced - num_group_columns; }
  int GroupSize(int g) const { return group_offset[g + 1] - group_offset[g]; }
};

// Lays out the free blocks of `problem` as `layout` names them (blocks the
// layout names that are constant or not in the problem are skipped).
// Returns false with `error` set when a free block of the problem is not in
// the layout, or a reprojection residual block holds two eliminated blocks
// (other residuals that hold several are laid out as Residual::coupled).
bool LayOutBlocks(const StructuredLayout& layout, ceres::Problem* problem,
                  StructuredBlocks* blocks, std::string* error);

}  // namespace structured
}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_REFINE_STRUCTURED_LAYOUT_H_
