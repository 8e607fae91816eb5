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
// (problems/orthonormality_error.h) over G by Levenberg–Marquardt. The cost
// has many local minima, so it screens kTripleStarts starts — the
// Tomasi-Kanade triple (the metric upgrade of Q̂'s first three columns,
// padded with zeros), then seeded random G — by kTripleScreenIterations
// iterations each on at most kTripleScreenFrames frames spread over the
// sequence, runs the kTripleKept lowest of them to convergence on at most
// kTriplePolishFrames frames, and the lowest of those on every frame. Costs
// within kTripleEqualCost per frame of the lowest count as equal (every
// exact triple of noise-free data does, docs/factorization.md): of those the
// triple whose scale c_t stays furthest from zero is kept (a triple whose
// weight passes near zero in some frame gives a poorly determined rotation
// there). The screening relies on a start bound for the global minimum
// converging in far fewer iterations than one bound for a local minimum, so
// that it is among the lowest after the screening (measured on the real
// sequences in docs/factorization.md, section 5). G is found up to G → α G U
// (scale, rotation, reflection: the global gauges).
//
// The sign of c_t is not fixed by the constraints (−Π R_t is Π R'_t for R_t
// turned by 180° about the optical axis, the frame reversed in depth).
// RotationsFromTriple chooses it per segment of frames: consecutive frames
// are linked into segments of one sign when the input is a time sequence
// (at least 90 % of consecutive pairs differ clearly between their two
// candidate signs; frames in random order keep one segment each), and every
// segment whose summed weak-perspective scale against the least-squares
// rigid shape is negative is turned (twice over).
#ifndef NRSFM_SOLVERS_START_CORRECTIVE_TRIPLE_H_
#define NRSFM_SOLVERS_START_CORRECTIVE_TRIPLE_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/model/measurements.h"
#include "core/model/status.h"

namespace nrsfm {

// Starts of G screened by SolveCorrectiveTriple: the Tomasi-Kanade triple,
// then random ones (the share of random starts that reach the global
// minimum is measured in docs/factorization.md, section 5).
inline constexpr int kTripleStarts = 32;
// Levenberg-Marquardt iterations of the screening, and its frames.
inline constexpr int kTripleScreenIterations = 10;
inline constexpr int kTripleScreenFrames = 100;
// Screened starts run to convergence, on how many frames, and the iteration
// limit of those solves.
inline constexpr int kTripleKept = 4;
inline constexpr int kTriplePolishFrames = 300;
// Cost per frame (½ Σ of the two dimensionless residuals) below which two
// minima are the same: residuals of ~1e-5, below the noise of any data.
inline constexpr double kTripleEqualCost = 1e-10;
inline constexpr int kTripleMaxIterations = 200;

struct CorrectiveTripleSummary {
  int sign_segments = 0;  // segments of one sign (F when not linked in time)
};

// `q_hat` is 2F × 3K (F ≥ 2, K ≥ 1). Fills `g` (3K × 3) with the start of
// lowest cost; `seed` seeds the random starts (core/math/random.h); the starts
// run on up to `num_threads` threads (the result does not depend on it).
// Errors on a matrix of the wrong shape and when no start converges.
Status SolveCorrectiveTriple(const Eigen::MatrixXd& q_hat, std::uint64_t seed,
                             int num_threads, Eigen::MatrixX3d* g);

// The rotations and scales of every frame of `centered` (one camera, every
// entry filled, translation removed): rank-3K SVD, SolveCorrectiveTriple,
// nearest scaled rotation per frame, signs by the rigid fit (header); also
// the least-squares rigid shape for those rotations and scales (3 × P).
// Errors when 3K exceeds 2F or P, or the tracks have rank < 3.
Status RotationsFromTriple(const Measurements& centered, int num_bases,
                           std::uint64_t seed, int num_threads,
                           std::vector<Eigen::Matrix3d>* rotations,
                           Eigen::VectorXd* scales,
                           Eigen::Matrix3Xd* rigid_shape,
                           CorrectiveTripleSummary* summary);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_START_CORRECTIVE_TRIPLE_H_
