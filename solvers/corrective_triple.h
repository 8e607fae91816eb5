// Camera rotations from the rank-3K factorisation by the orthonormality
// constraints of one corrective triple (Xiao, Chai and Kanade 2004; Akhter,
// Sheikh and Khan 2009, "In defense of orthonormality constraints for
// nonrigid structure from motion"); docs/factorization.md, section 5, has
// the derivation.
//
// With the rank-3K SVD of the centred tracks, W̃ ≈ Q̂ B̂ (Q̂ 2F × 3K), a column
// triple G (3K × 3) of the corrective matrix makes every frame's rows
// [q_t1; q_t2] G a scaled rotation c_t Π R_t. SolveCorrectiveTriple
// minimises the scale-free orthonormality residuals of every frame
// (problems/orthonormality_error.h) over G by Levenberg–Marquardt from
// kTripleStarts starts and keeps the lowest cost: first the Tomasi-Kanade
// triple (the metric upgrade of Q̂'s first three columns, padded with
// zeros), then seeded random G. G is found up to G → α G U (scale, rotation,
// reflection: the global gauges).
//
// The sign of c_t is not fixed by the constraints (−Π R_t is Π R'_t for R_t
// turned by 180° about the optical axis, the frame reversed in depth).
// RotationsFromTriple chooses it per segment of frames: consecutive frames
// are linked into segments of one sign when the input is a time sequence
// (at least 90 % of consecutive pairs differ clearly between their two
// candidate signs; frames in random order keep one segment each), and every
// segment whose summed weak-perspective scale against the least-squares
// rigid shape is negative is turned (twice over).
#ifndef NRSFM_SOLVERS_CORRECTIVE_TRIPLE_H_
#define NRSFM_SOLVERS_CORRECTIVE_TRIPLE_H_

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/measurements.h"
#include "core/status.h"

namespace nrsfm {

// Starts of G tried by SolveCorrectiveTriple: the Tomasi-Kanade triple, then
// random ones (a quarter of random starts reach the lowest cost on pickup).
inline constexpr int kTripleStarts = 16;
// Levenberg-Marquardt iterations per start.
inline constexpr int kTripleMaxIterations = 200;

struct CorrectiveTripleSummary {
  bool temporal_signs = false;  // whether frames were linked in time
  int sign_segments = 0;        // segments of one sign (F when not linked)
};

// `q_hat` is 2F × 3K (F ≥ 2, K ≥ 1). Fills `g` (3K × 3) with the start of
// lowest cost; `seed` seeds the random starts (core/random.h). Errors on a
// matrix of the wrong shape and when no start converges.
Status SolveCorrectiveTriple(const Eigen::MatrixXd& q_hat, std::uint64_t seed,
                             Eigen::MatrixX3d* g);

// The rotations and scales of every frame of `centered` (one camera, every
// entry filled, translation removed): rank-3K SVD, SolveCorrectiveTriple,
// nearest scaled rotation per frame, signs by the rigid fit (header); also
// the least-squares rigid shape for those rotations and scales (3 × P).
// Errors when 3K exceeds 2F or P, or the tracks have rank < 3.
Status RotationsFromTriple(const Measurements& centered, int num_bases,
                           std::uint64_t seed,
                           std::vector<Eigen::Matrix3d>* rotations,
                           Eigen::VectorXd* scales, Eigen::Matrix3Xd* rigid_shape,
                           CorrectiveTripleSummary* summary);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_CORRECTIVE_TRIPLE_H_
