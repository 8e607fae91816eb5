// The update of every rotation block of the problem. A rotation is stored as
// an angle-axis vector ω (R = exp([ω]×), radians); Levenberg–Marquardt steps
// δ ∈ R³ are taken in the rotation's own body frame,
//
//   Plus(ω, δ) = log(exp([ω]×) exp([δ]×)),
//
// instead of ω + δ. The additive update's Jacobian is far from orthogonal
// when |ω| is large (it is singular at |ω| = 2π), which makes the first LM
// steps of a refinement rejected one after another; the multiplicative
// update is isotropic at every ω (measured in docs/performance.md).
#ifndef NRSFM_PROBLEMS_ROTATION_MANIFOLD_H_
#define NRSFM_PROBLEMS_ROTATION_MANIFOLD_H_

#include <ceres/manifold.h>

namespace nrsfm {

class AngleAxisManifold : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 3; }
  int TangentSize() const override { return 3; }
  // out = log(exp(x) exp(delta)), |out| ≤ π.
  bool Plus(const double* x, const double* delta, double* out) const override;
  // d Plus(x, δ) / dδ at δ = 0: the inverse right Jacobian of SO(3) at x,
  //   J = I + ½[x]× + (1/θ² − (1 + cos θ)/(2θ sin θ)) [x]×²,  θ = |x|,
  // row-major 3 × 3.
  bool PlusJacobian(const double* x, double* jacobian) const override;
  // out = log(exp(x)ᵀ exp(y)), so that Plus(x, Minus(y, x)) = y.
  bool Minus(const double* y, const double* x, double* out) const override;
  // d Minus(y, x) / dy at y = x: the inverse of PlusJacobian(x).
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_ROTATION_MANIFOLD_H_
