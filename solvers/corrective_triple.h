// Camera rotations from the rank-3K factorisation by the orthonormality
// constraints of one corrective triple (Xiao, Chai and Kanade 2004; Akhter,
// Sheikh and Khan 2009, "In defense of orthonormality constraints for
// nonrigid structure from motion"; Dai, Li and He 2012 use the same
// constraints on the Gram matrix).
//
// With the rank-3K SVD of the centred tracks, W̃ ≈ Q̂ B̂ (Q̂ 2F × 3K), the true
// motion is Q̂ A for an unknown invertible 3K × 3K A. Each column triple G of
// A (3K × 3) satisfies, for every frame t with rows q_t1, q_t2 of Q̂,
//   [q_t1; q_t2] G = c_t Π R_t     (c_t a frame's weight of that triple),
// so a_1 = q_t1 G and a_2 = q_t2 G have equal norms and are orthogonal.
// SolveCorrectiveTriple minimises, over G, the scale-free residuals
//   r_t = ( (|a_1|² − |a_2|²), 2 a_1·a_2 ) / (|a_1|² + |a_2|²)
// (each in [−1, 1]; 0 for an exact scaled rotation) with Ceres
// Levenberg-Marquardt from several starts, keeping the lowest cost: first
// the Tomasi-Kanade triple (the metric upgrade of the first three columns of
// Q̂, padded with zeros: the triple of the dominant, mean-shape-like
// component, whose weight c_t stays away from zero), then seeded random G.
// The cost has many local minima; on pickup (K = 12) a quarter of random
// starts reach the lowest one, the Tomasi-Kanade start does. A triple whose
// weight c_t passes near zero in some frames gives garbage rotations there. The cost is invariant to G ← α G U (scale, rotation, reflection:
// the global gauges); Akhter et al. show every G with zero cost gives the
// true rotations up to them on noise-free data, whereas Bregler's per-frame
// rank-1 sub-blocks (solvers/factorization_start.h) do not.
//
// The sign of c_t is not fixed by the constraints: −Π R_t = Π R'_t with R'_t
// R_t turned by 180° about the optical axis, and the frame's shape reversed
// in depth. RotationsFromTriple fixes it in two steps. (1) In a time
// sequence, consecutive rotations are close with one relative sign and far
// apart with the other: frames are linked into segments of consistent sign
// (a link needs the two candidates to differ clearly; the sequence counts as
// ordered in time only when at least 90 % of consecutive pairs link, so
// frames in random order keep one segment each). (2) With the nearest
// rotations it fits one rigid shape to all frames by least squares and turns
// every segment whose summed weak-perspective scale against that shape is
// negative, twice over. Per-frame decisions alone (step 2 without step 1)
// reverse whole stretches of a sequence where the object is far from its
// mean shape (e.g. a person bending down).
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
