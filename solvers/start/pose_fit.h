// Weak-perspective (scaled orthographic) pose of one view from 2D-3D
// correspondences, the per-frame pieces of the closed-form starts
// (docs/factorization.md: the metric upgrade's nearest rotations, the
// alternation's rotation updates, the extra cameras' poses).
//
// Camera model (core/model/model.h): w_p = s · Π · R · x_p with Π = [I_2 0],
// R ∈ SO(3), s > 0; w_p are centred 2D observations (translation removed),
// x_p object-frame 3D points, both with corresponding columns.
#ifndef NRSFM_SOLVERS_START_POSE_FIT_H_
#define NRSFM_SOLVERS_START_POSE_FIT_H_

#include <Eigen/Core>

namespace nrsfm {

// The weak-perspective camera nearest to a 2 × 3 matrix m ≈ s Π R: with the
// thin SVD m = U Σ Vᵀ, the rows of U Vᵀ are the orthonormal pair nearest to m
// (Frobenius), s = (σ₁ + σ₂) / 2 the least-squares scale for them, and the
// third row of R is their cross product (so det R = +1). m = 0 gives R = I,
// s = 0.
void ScaledRotationFromTwoRows(const Eigen::Matrix<double, 2, 3>& m,
                               Eigen::Matrix3d* rotation, double* scale);

// Sum of squared residuals Σ_p ||w_p − s Π R x_p||².
double PoseCost(const Eigen::Matrix2Xd& observed,
                const Eigen::Matrix3Xd& points, double scale,
                const Eigen::Matrix3d& rotation);

// Gauss-Newton on the rotation only (s fixed), linearised as Torresani et al.
// 2001 do:
//   w_p ≈ s Π (I + [ω]×) R x_p,   R ← exp([ω]×) R,
// each step kept only when it lowers PoseCost (so the cost never increases).
// Stops after `max_steps` steps or when a step does not help. Returns the
// final cost.
double RefineRotation(const Eigen::Matrix2Xd& observed,
                      const Eigen::Matrix3Xd& points, double scale,
                      int max_steps, Eigen::Matrix3d* rotation);

// Full weak-perspective fit of s and R (the pose of an extra camera):
// the affine least-squares 2 × 3 map M = W Xᵀ (X Xᵀ)⁻¹, its nearest scaled
// rotation (ScaledRotationFromTwoRows), then up to `max_steps` rounds of
// RefineRotation and the closed-form scale s = Σ⟨w_p, Π R x_p⟩ / Σ||Π R x_p||².
// Exact on noise-free data. Returns false (outputs unchanged) when the points
// do not span 3D (X Xᵀ numerically singular: fewer than 4 points, or
// coplanar/collinear points), or the fitted scale is not positive.
bool FitWeakPerspectivePose(const Eigen::Matrix2Xd& observed,
                            const Eigen::Matrix3Xd& points, int max_steps,
                            Eigen::Matrix3d* rotation, double* scale);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_START_POSE_FIT_H_
