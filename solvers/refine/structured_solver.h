// Levenberg–Marquardt for the one Ceres problem of a reconstruction when its
// point blocks are an independent set (no residual block holds two of them)
// and the frames form a chain (temporal terms couple a frame only with its
// neighbours).
//
// The problem is the ceres::Problem the builder made — the same residual
// blocks, cost functions, losses and manifolds Ceres would use; only the
// linear algebra differs. Each LM step solves
//   (JᵀJ + μ D) δ = −Jᵀr,   D = diag(JᵀJ) clamped as Ceres does, μ = 1/radius
// (Ceres' Levenberg–Marquardt step, trust-region update and constants, read
// from ceres::Solver::Options' defaults) by eliminating
// the point blocks exactly (Schur complement) and solving the reduced system
// over the frame blocks by preconditioned conjugate gradients. The
// preconditioner is the frame blocks' part of JᵀJ + μD — every coupling that
// residual blocks make between frames up to `band` apart (temporal terms) —
// factorised as a block band; the coupling between frames through shared
// points (dense: every frame sees every point) is left to CG, and so is each
// frame's own Schur-complement block (− J_fᵀ J_p C̃⁻¹ J_pᵀ J_f), which is not
// added to the band (docs/performance.md). Shared blocks that touch many
// frames (rig rotations, …) form a dense border of the preconditioner.
// Ceres 2.1's own iterative Schur solver cannot use such a preconditioner
// (its JACOBI and SCHUR_JACOBI ignore the chain).
//
// The parts, one file each (namespace nrsfm::structured): structured_layout
// (blocks as columns, residual blocks as rows), structured_jacobian
// (evaluation, stored Jacobian, products), reprojection_panel (the
// reprojection residuals' products as matrix products over views × points),
// schur_elimination, band_preconditioner, conjugate_gradients; this file's
// .cc: the LM loop. Products with the Jacobian are formed from the
// parameters where a cost function can (problems/jacobian_product.h; the
// panel, the basis factor, the Gram blocks: docs/performance.md), else read
// from the stored Jacobian. Sums over residual blocks are added in pieces
// fixed by the problem (core/math/parallel_for.h, ParallelForPieces): the
// same bits for any thread count.
#ifndef NRSFM_SOLVERS_REFINE_STRUCTURED_SOLVER_H_
#define NRSFM_SOLVERS_REFINE_STRUCTURED_SOLVER_H_

#include <ceres/problem.h>

#include <functional>
#include <string>
#include <vector>

#include "solvers/refine/solver_options.h"

namespace nrsfm {

namespace structured {
struct StructuredBlocks;  // solvers/refine/structured_layout.h
}  // namespace structured

struct StructuredLayout {
  // The reduced side: one group of blocks per frame, in time order; blocks of
  // a group are given in the order of their columns (e.g. ω_t, T_t, l_t).
  std::vector<std::vector<double*>> groups;
  // Reduced-side blocks shared by many frames (dense border).
  std::vector<double*> globals;
  // Blocks eliminated exactly (points); no residual block may hold two.
  std::vector<double*> eliminated;
};

struct StructuredSolverOptions {
  // Iterations, tolerances, time limit, first radius, threads (results are
  // identical for any count), progress (iteration 0 = the start) and
  // stop_requested (asked before every step; true ends the solve,
  // summary.stopped), as for Ceres, and the conjugate gradients'
  // cg_relative_tolerance and max_cg_iterations; linear_solver and
  // verbosity are not read.
  SolverOptions solver;
};

struct StructuredSolverSummary {
  bool usable = false;
  std::string message;  // why the solve stopped
  // by a tolerance (not by the iteration or time limit)
  bool converged = false;
  bool stopped = false;  // by options.stop_requested
  double initial_cost = 0.0, final_cost = 0.0;
  int iterations = 0;     // LM iterations (accepted and rejected)
  int cg_iterations = 0;  // in all
  double evaluate_seconds = 0.0, preconditioner_seconds = 0.0, cg_seconds = 0.0,
         total_seconds = 0.0;
  // Reading the problem into the solver's layout and allocating its buffers
  // (before the iterations; not in total_seconds).
  double setup_seconds = 0.0;
};

// Solves in place (the blocks hold the result). Returns false with `error` set
// when the layout does not fit the problem (a free block of the problem that
// the layout does not name, or a reprojection residual block that holds two
// eliminated blocks): the caller then uses Ceres' own solver.
bool SolveStructured(const StructuredSolverOptions& options,
                     const StructuredLayout& layout, ceres::Problem* problem,
                     StructuredSolverSummary* summary, std::string* error);
// The same with the problem's layout kept in `kept` for the next solve of the
// same problem: laid out into it when it holds none, read from it otherwise
// (then `layout` is not read; the problem, its blocks' storage and their
// constness must not have changed since).
bool SolveStructured(const StructuredSolverOptions& options,
                     const StructuredLayout& layout, ceres::Problem* problem,
                     StructuredSolverSummary* summary, std::string* error,
                     structured::StructuredBlocks* kept);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_REFINE_STRUCTURED_SOLVER_H_
