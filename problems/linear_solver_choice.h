// The linear solver of the Levenberg–Marquardt steps, and the `auto` rule
// (docs/problem.md; the measurements behind it in docs/performance.md).
//
// A reprojection residual couples one view's rotation / translation (and
// scale), one frame's weights and one point's basis column, so the point
// blocks b_p (3K each) are an independent set and can be Schur-eliminated.
// Every point is normally seen in almost every frame, so the reduced system
// over the frame blocks is dense ((5 + K)F unknowns) and a direct solver
// pays O(F · (3KP)²) or O(P · ((5 + K)F)²) flops per step to form it, while
// the iterative solvers pay O(nnz(J)) per conjugate-gradient step. The rule
// (ChooseLinearSolver):
//   free point blocks → structured (points eliminated — one by one, or,
//   when a term couples points (the Delaunay smoothness), together by a
//   sparse factorisation along the couplings — conjugate gradients over the
//   frames with a block-band preconditioner that is exact for every coupling
//   the temporal terms make; solvers/refine/structured_solver.h, a minimiser of
//   its own: solvers/refine/minimizer_choice.h). Without temporal terms it does
//   what ITERATIVE_SCHUR with JACOBI does, with cheaper products
//   (docs/performance.md); a problem whose blocks it cannot lay out (a free
//   block of an unknown kind) falls back to ITERATIVE_SCHUR (CGNR when
//   points are coupled: Ceres cannot eliminate them)
//   no free point block (poses / weights only; JᵀJ is then block-diagonal
//   per frame plus what other terms couple)              →
//   SPARSE_NORMAL_CHOLESKY
// The iterative solvers use the JACOBI preconditioner (SCHUR_JACOBI visits
// every pair of frame blocks that share a point to build).
#ifndef NRSFM_PROBLEMS_LINEAR_SOLVER_CHOICE_H_
#define NRSFM_PROBLEMS_LINEAR_SOLVER_CHOICE_H_

#include <ceres/solver.h>

#include <string>

#include "core/model/status.h"
#include "problems/problem_builder.h"

namespace nrsfm {

enum class LinearSolverChoice {
  kAuto,            // the rule above, from the problem's structure
  kDenseSchur,      // points eliminated, dense reduced system
  kSparseSchur,     // points eliminated, sparse Cholesky of the rest
  kIterativeSchur,  // points eliminated, CG on the implicit reduced system,
                    // JACOBI
  kSparseNormalCholesky,  // sparse Cholesky of JᵀJ
  kCgnr,                  // CG on the normal equations, JACOBI
  kDenseQr,               // dense QR of J (tiny problems only)
  kStructured,            // points eliminated, CG over the frame chain with a
                          // block-band preconditioner: not a Ceres linear
  // solver but a minimiser (solvers/refine/minimizer_choice.h)
};
// "auto", "dense_schur", "sparse_schur", "iterative_schur",
// "sparse_normal_cholesky", "cgnr", "dense_qr", "structured"; an error lists
// them.
Status ParseLinearSolver(const std::string& name, LinearSolverChoice* choice);
const char* LinearSolverName(LinearSolverChoice choice);

// What the rule and the memory checks look at (free parameters only).
struct ProblemStructure {
  int num_point_blocks = 0;      // non-constant basis columns
  int num_point_parameters = 0;  // their total size, 3K each
  int num_other_parameters = 0;  // every other non-constant parameter
  int num_residuals = 0;         // rows of J
  // Upper bound on the entries of the reduced matrix with the points
  // eliminated (its fill: every pair of parameters that share a point).
  double schur_matrix_entries = 0.0;
  bool points_are_independent = true;  // see ProblemBuilder
  // Largest distance in time between two frames whose free blocks one
  // residual block holds (0: no residual couples two frames).
  int frame_coupling = 0;
};
ProblemStructure DescribeProblem(ProblemBuilder* builder);
// Only num_point_blocks, num_point_parameters and points_are_independent
// (the rest left at their defaults): what ChooseLinearSolver reads, without
// DescribeProblem's scan of which blocks share a residual block (seconds on
// millions of residual blocks).
ProblemStructure DescribePointBlocks(ProblemBuilder* builder);

// The `auto` rule (above); reads structure.num_point_blocks only. Never
// returns kAuto.
LinearSolverChoice ChooseLinearSolver(const ProblemStructure& structure);

// Sets options->linear_solver_type, preconditioner_type and
// linear_solver_ordering (points eliminated for the Schur solvers) for
// `choice` (kAuto resolved by ChooseLinearSolver). When the point blocks
// cannot be eliminated (not an independent set, or all constant) a Schur
// solver gets no ordering and Ceres picks an independent set itself. Errors,
// instead of exhausting the memory, when DENSE_QR, DENSE_SCHUR or the
// reduced matrix of SPARSE_SCHUR would need more than kMaxDenseBytes.
// `*used` is the resolved choice. kStructured is not a Ceres linear solver:
// an error (solvers/refine/minimizer_choice.h sends it to its own minimiser).
// Determinism: every solver gets an explicit ordering by block kind (Ceres
// would otherwise order blocks by address, so the rounding would depend on
// the heap layout), and DENSE_SCHUR / SPARSE_SCHUR are set to one thread:
// Ceres 2.1's parallel Schur elimination adds into the reduced matrix in
// thread-scheduling order, so its rounding would depend on the scheduling.
inline constexpr double kMaxDenseBytes = 2.0e9;
Status ConfigureLinearSolver(LinearSolverChoice choice, ProblemBuilder* builder,
                             ceres::Solver::Options* options,
                             LinearSolverChoice* used);

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_LINEAR_SOLVER_CHOICE_H_
