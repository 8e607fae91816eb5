// The linear solver of the Levenberg–Marquardt steps, and the `auto` rule.
//
// Structure of the reprojection term (DESIGN.md §2): a residual couples one
// view's rotation/translation (and scale), one frame's weights and one point's
// basis column. So the point blocks b_p (3K each) form an independent set
// and can be Schur-eliminated; the per-frame blocks (ω_t, T_t, l_t) share
// residuals with each other, so "the frames" are not an independent set — of
// them only one kind at a time (e.g. all l_t) could be eliminated. Every
// point is normally seen in almost every frame, so the reduced system over
// the frame blocks is dense: (5 + K)F unknowns. Eliminating the frames'
// weights instead leaves (5F + 3KP) unknowns, dense in the points. Either
// way a direct solver pays O(F · (3KP)²) or O(P · ((5 + K)F)²) flops per step
// to form the reduced matrix; the iterative solvers pay O(nnz(J)) per
// conjugate-gradient step.
//
// Measured with nrsfm_solver_timing --mode=table (bench/refine_benchmark.cc):
// Release, 1 thread, random-basis data with noise 0.01 (~2 % of the data
// spread), every solver from the same closed-form start, 60 s limit per
// solve (checked between iterations; * = stopped by it). The 2-core machine
// was shared with other builds (load 2-8): wall times are inflated up to ~3×,
// compare them within a row set. Final cost = Ceres cost ½ Σ ||r||².
//
//   (1102, 41, 12), drink-sized: 45182 obs., 18734 frame + 1476 point params
//     solver                  LM it   s/it   total s   final cost
//     dense_schur             refused: reduced matrix 18734² = 2.8 GB, ~2e12 flop/step
//     sparse_schur            refused: the same (dense) reduced matrix
//     iterative_schur            8    0.51      4.4    3.527398
//     sparse_normal_cholesky     2*  44        89*    13.12 (not converged)
//     cgnr                      13    0.96     12.9    3.527398
//   (300, 110, 5): 33000 obs., 3000 frame + 1650 point params
//     dense_schur                3*  20.7      62.5*   3.077761
//     sparse_schur               2*  39.0      78.7*   3.077767
//     iterative_schur            4    0.39      1.9    3.077761
//     sparse_normal_cholesky     4   16.0      64.5    3.077761
//     cgnr                       5    0.33      1.9    3.077761
//   (300, 5000, 5): 1.5 M obs., 3000 frame + 75000 point params
//     dense_schur                2* 566      1151*   146.2990 (not converged)
//     sparse_schur               2* 821      1660*   146.2990 (not converged)
//     iterative_schur            5    7.7      58      145.9893
//     sparse_normal_cholesky     fails: CHOLMOD "problem too large" (Ceres
//                                FAILURE, not usable)
//     cgnr                       6*  13.3      87*    145.9893
//   Smaller, (30, 15, 3) / (100, 40, 3), ms per LM iteration (51 iterations
//   each): iterative_schur 2 / 21, cgnr 3 / 26, sparse_normal_cholesky
//   10 / 47, dense_schur 11 / 514, sparse_schur 18 / 618, dense_qr 91 / -.
// Why the direct solvers lose even when small: every point is seen in every
// frame, so eliminating a point touches all 3F frame blocks and Ceres' Schur
// eliminator visits ~(3F)²/2 block pairs per point; SPARSE_NORMAL_CHOLESKY
// fills in the same way. ITERATIVE_SCHUR uses the JACOBI preconditioner:
// SCHUR_JACOBI costs the same pair visits to build (4.7 s per LM iteration
// on drink-sized data against 0.3 s with JACOBI, for the same iterates).
// Eliminating the weights l_t instead of the points was slower for every
// preconditioner tried.
//
// The rule (ChooseLinearSolver):
//   free point blocks, no residual coupling two points  → ITERATIVE_SCHUR
//   no free point block (poses / weights only; JᵀJ is then block-diagonal
//   per frame plus what other terms couple)              → SPARSE_NORMAL_CHOLESKY
//   point blocks coupled (e.g. basis smoothness)         → CGNR (the points
//   cannot be eliminated and the normal equations fill as above)
//
// Extra terms (problems/extra_terms.h). Temporal and rigidity residuals couple
// only non-point blocks, so the points stay independent and the rule keeps
// iterative_schur. Smoothness residuals couple two points: the rule then
// takes cgnr. Measured on the shoe (F = 500, M = 2, P = 110, K = 4, noise
// 0.01, factorisation start, 20 LM iterations, 1 thread, loaded 2-core
// machine; s/it, final cost from 28.98):
//   smoothness λ = 0.01:  cgnr 0.60 (cost 8.998), iterative_schur (Ceres
//     picks the eliminated set) 0.55 (8.976), sparse_schur 4.2 (8.910),
//     dense_schur 9.7 (8.910), sparse_normal_cholesky 7.2 (8.910);
//   no extra term: iterative_schur 0.38; temporal (λ 1, 1): iterative_schur
//     0.60; rigidity (λ 100): iterative_schur 0.68.
// The direct solvers reach a lower cost per iteration but cost 7-16× more
// per iteration; cgnr and iterative_schur are within the machine's noise.
#ifndef NRSFM_PROBLEMS_LINEAR_SOLVER_CHOICE_H_
#define NRSFM_PROBLEMS_LINEAR_SOLVER_CHOICE_H_

#include <string>

#include <ceres/solver.h>

#include "core/status.h"
#include "problems/problem_builder.h"

namespace nrsfm {

enum class LinearSolverChoice {
  kAuto,                  // the rule below, from the problem's structure
  kDenseSchur,            // points eliminated, dense reduced system
  kSparseSchur,           // points eliminated, sparse Cholesky of the rest
  kIterativeSchur,        // points eliminated, CG on the implicit reduced system, JACOBI
  kSparseNormalCholesky,  // sparse Cholesky of JᵀJ
  kCgnr,                  // CG on the normal equations, JACOBI
  kDenseQr,               // dense QR of J (tiny problems only)
};
// "auto", "dense_schur", "sparse_schur", "iterative_schur",
// "sparse_normal_cholesky", "cgnr", "dense_qr"; an error lists them.
Status ParseLinearSolver(const std::string& name, LinearSolverChoice* choice);
const char* LinearSolverName(LinearSolverChoice choice);

// What the rule and the memory checks look at (free parameters only).
struct ProblemStructure {
  int num_point_blocks = 0;           // non-constant basis columns
  int num_point_parameters = 0;       // their total size, 3K each
  int num_other_parameters = 0;       // every other non-constant parameter
  int num_residuals = 0;              // rows of J
  // Upper bound on the entries of the reduced matrix with the points
  // eliminated (its fill: every pair of parameters that share a point).
  double schur_matrix_entries = 0.0;
  bool points_are_independent = true; // see ProblemBuilder
};
ProblemStructure DescribeProblem(ProblemBuilder* builder);

// The `auto` rule (see the table above). Never returns kAuto.
LinearSolverChoice ChooseLinearSolver(const ProblemStructure& structure);

// Sets options->linear_solver_type, preconditioner_type and
// linear_solver_ordering (points eliminated for the Schur solvers) for
// `choice` (kAuto resolved by ChooseLinearSolver). When the point blocks
// cannot be eliminated (not an independent set, or all constant) a Schur
// solver gets no ordering and Ceres picks an independent set itself. Errors,
// instead of exhausting the memory, when DENSE_QR, DENSE_SCHUR or the
// reduced matrix of SPARSE_SCHUR would need more than kMaxDenseBytes.
// `*used` is the resolved choice.
// Determinism: every solver gets an explicit ordering by block kind (Ceres
// would otherwise order blocks by address, so the rounding would depend on
// the heap layout), and DENSE_SCHUR / SPARSE_SCHUR are set to one thread:
// Ceres 2.1's parallel Schur elimination adds into the reduced matrix in
// thread-scheduling order, so two runs differed in the last bits.
inline constexpr double kMaxDenseBytes = 2.0e9;
Status ConfigureLinearSolver(LinearSolverChoice choice, ProblemBuilder* builder,
                             ceres::Solver::Options* options,
                             LinearSolverChoice* used);

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_LINEAR_SOLVER_CHOICE_H_
