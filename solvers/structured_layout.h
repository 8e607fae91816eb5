// The structured solver's view of a ceres::Problem
// (solvers/structured_solver.h): its free parameter blocks as columns and its
// residual blocks as rows.
//
// Columns are tangent-space coordinates (a block with a manifold has
// Manifold::TangentSize() columns). The reduced side holds one group of
// columns per frame, in time order, then the shared blocks (the dense
// border); the eliminated side holds the point blocks. A block's columns are
// [offset, offset + size) of the reduced or of the eliminated vector. A
// residual block's rows are [row, row + m) of the residual vector; its
// Jacobian, when stored (solvers/structured_jacobian.h), is m × width,
// row-major, its free slots' columns in parameter order (constant blocks
// have none). Blocks are named by their index in StructuredBlocks::blocks.
//
// Assumes the problem is not changed while the blocks are in use (the
// pointers to cost functions, losses, manifolds and values are the
// problem's).
#ifndef NRSFM_SOLVERS_STRUCTURED_LAYOUT_H_
#define NRSFM_SOLVERS_STRUCTURED_LAYOUT_H_

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>

#include <cstddef>
#include <string>
#include <vector>

#include "problems/jacobian_product.h"
#include "problems/reprojection_cost_function.h"
#include "solvers/structured_solver.h"

namespace nrsfm {
namespace structured {

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

struct Residual {
  const ceres::CostFunction* cost = nullptr;
  const ceres::LossFunction* loss = nullptr;
  int m = 0;            // residuals
  int row = 0;          // first row in r
  int width = 0;        // columns of the stored Jacobian
  std::size_t jac = 0;  // start in the Jacobian buffer
  std::vector<double*> parameters;
  std::vector<int> slot_block;   // Block index per parameter, -1 = constant
  std::vector<int> slot_jcol;    // column of the slot in the stored Jacobian
  std::vector<Segment> reduced;  // merged per group
  int eliminated = -1;           // Block index, -1 = none
  int eliminated_jcol = 0;
  // Products with its Jacobian from its parameters
  // (problems/jacobian_product.h), used in the conjugate gradients instead of
  // the stored Jacobian.
  const JacobianProduct* product = nullptr;
  // A reprojection residual without a robust loss whose eliminated block is
  // its basis block: that block's Jacobian l_k · A is not stored, only A
  // (2 × 3 at `factor` of the factor buffer), and l is read from the weights
  // block (problems/reprojection_cost_function.h, BasisJacobianFactor).
  const BasisJacobianFactor* basis_factor = nullptr;
  std::size_t factor = 0;
  const double* weights = nullptr;
  int num_bases = 0;
  // The product also provides its Gram blocks (JacobianProduct::ProvidesGram):
  // no Jacobian is stored for this residual at all.
  bool gram = false;

  // The parameter slot of the eliminated block, -1 when there is none.
  int EliminatedSlot() const {
    for (std::size_t k = 0; k < slot_block.size(); ++k) {
      if (slot_block[k] == eliminated) return static_cast<int>(k);
    }
    return -1;
  }
};

// A reference from a target (group, shared block or eliminated block) to the
// residual segments that touch it.
struct Ref {
  int residual;
  int segment;  // index into Residual::reduced, or -1 for the eliminated part
};

struct StructuredBlocks {
  std::vector<Block> blocks;
  std::vector<int>
      group_offset;  // columns of group g: [g_off[g], g_off[g + 1])
  int num_group_columns = 0, num_reduced = 0, num_eliminated = 0, num_rows = 0;
  // Largest distance between two groups whose blocks one residual block holds.
  int band = 0;
  std::vector<int> eliminated_blocks;  // Block indices, in the layout's order
  std::vector<Residual> residuals;     // in the problem's order
  // Per group, per eliminated block: the residual segments that touch it.
  std::vector<std::vector<Ref>> group_refs, eliminated_refs;
  std::vector<int> residuals_with_shared;  // residuals that hold a shared block
  std::size_t jacobian_size = 0;           // values of the stored Jacobian
  std::size_t factors_size = 0;  // values of the basis factors A, 6 each

  int num_groups() const { return static_cast<int>(group_refs.size()); }
  int num_shared() const { return num_reduced - num_group_columns; }
  int GroupSize(int g) const { return group_offset[g + 1] - group_offset[g]; }
};

// Lays out the free blocks of `problem` as `layout` names them (blocks the
// layout names that are constant or not in the problem are skipped).
// Returns false with `error` set when a free block of the problem is not in
// the layout or a residual block holds two eliminated blocks.
bool LayOutBlocks(const StructuredLayout& layout, ceres::Problem* problem,
                  StructuredBlocks* blocks, std::string* error);

}  // namespace structured
}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_STRUCTURED_LAYOUT_H_
