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
// Levenberg-Marquardt from several seeded random G, keeping the lowest
// cost. The cost is invariant to G ← α G U (scale, rotation, reflection:
// the global gauges); Akhter et al. show every G with zero cost gives the
// true rotations up to them on noise-free data, whereas Bregler's per-frame
// rank-1 sub-blocks (solvers/factorization_start.h) do not.
//
// The sign of c_t is not fixed by the constraints: −Π R_t = Π R'_t with R'_t
// R_t turned by 180° about the optical axis. RotationsFromTriple picks each
// frame's sign by the rigid fit: with the nearest rotations, it fits one
// rigid shape to all frames by least squares and keeps, per frame, the sign
// whose weak-perspective fit of that shape is better, twice over.
#ifndef NRSFM_SOLVERS_CORRECTIVE_TRIPLE_H_
#define NRSFM_SOLVERS_CORRECTIVE_TRIPLE_H_

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/measurements.h"
#include "core/status.h"

namespace nrsfm {

struct CorrectiveTripleOptions {
  int num_starts = 8;        // random starts of G, ≥ 1
  int max_iterations = 200;  // LM iterations per start, ≥ 1
  std::uint64_t seed = 1;    // of the random starts (mt19937_64, own Box-Muller)
  Status Check() const;
};

struct CorrectiveTripleSummary {
  double cost = 0.0;   // ½ Σ_t |r_t|² of the kept G (0 = exact)
  double rms = 0.0;    // sqrt(2 cost / 2F): RMS of the residuals above
  int best_start = 0;  // which start was kept
  int sign_flips = 0;  // sign reversals the rigid fit made (both rounds counted)
};

// `q_hat` is 2F × 3K (F ≥ 2, K ≥ 1). Fills `g` (3K × 3).
Status SolveCorrectiveTriple(const Eigen::MatrixXd& q_hat,
                             const CorrectiveTripleOptions& options,
                             Eigen::MatrixX3d* g, CorrectiveTripleSummary* summary);

// The rotations and scales of every frame of `centered` (one camera, every
// entry filled, translation removed): rank-3K SVD, SolveCorrectiveTriple,
// nearest scaled rotation per frame, signs by the rigid fit (header); also
// the least-squares rigid shape for those rotations and scales (3 × P).
// Errors when 3K exceeds 2F or P, or the tracks have rank < 3.
Status RotationsFromTriple(const Measurements& centered, int num_bases,
                           const CorrectiveTripleOptions& options,
                           std::vector<Eigen::Matrix3d>* rotations,
                           Eigen::VectorXd* scales, Eigen::Matrix3Xd* rigid_shape,
                           CorrectiveTripleSummary* summary);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_CORRECTIVE_TRIPLE_H_
