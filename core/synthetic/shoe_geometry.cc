#include "core/synthetic/shoe_geometry.h"

#include <Eigen/LU>
#include <cmath>
#include <iterator>

#include "core/synthetic/synthetic_common.h"

namespace nrsfm {
namespace synthetic {
namespace {

// along +z at the lateral side, from above once pitched).
constexpr double kHalfLength = 0.5;
constexpr double kSoleY = -0.11;
// e; the unit surface is Σ|u_i|^(2/e) = 1.
constexpr double kSuperExponent = 0.5;
constexpr double kRigScale = 0.9;  // s_t1 / s_t0

// Half height (heel raised, toe low) and half width (tapered toe) at x, and
// their derivatives.
double HalfHeight(double x) {
  return 0.11 + 0.05 * (1.0 - SmoothStep(-0.35, 0.05, x)) -
         0.04 * SmoothStep(0.15, 0.5, x);
}
double HalfHeightDerivative(double x) {
  return -0.05 * SmoothStepDerivative(-0.35, 0.05, x) -
         0.04 * SmoothStepDerivative(0.15, 0.5, x);
}
double HalfWidth(double x) {
  return 0.16 - 0.06 * SmoothStep(0.1, 0.5, x) -
         0.02 * (1.0 - SmoothStep(-0.5, -0.25, x));
}
double HalfWidthDerivative(double x) {
  return -0.06 * SmoothStepDerivative(0.1, 0.5, x) +
         0.02 * SmoothStepDerivative(-0.5, -0.25, x);
}

}  // namespace

// Point and outward unit normal of the shoe at surface coordinates
// (s, theta): s ∈ (−1, 1) runs from heel to toe, theta is the direction of
// the point in the cross-section (0 = up, −π/2 = lateral). On the unit
// superellipsoid g(u) = Σ|u_i|^m = 1 (m = 2/e) the point is
//   u = (s, ρ r(θ) cos θ, ρ r(θ) sin θ),  ρ = (1 − |s|^m)^(1/m),
//   r(θ) = (|cos θ|^m + |sin θ|^m)^(−1/m);
// it is mapped by φ(u) = (A u1, h(x) u2 + h(x) + kSoleY, w(x) u3), x = A u1,
// and the normal is J⁻ᵀ ∇g(u), J = ∂φ/∂u.
void ShoeSurface(double s, double theta, Eigen::Vector3d* point,
                 Eigen::Vector3d* normal) {
  const double m = 2.0 / kSuperExponent;
  const double c = std::cos(theta), d = std::sin(theta);
  const double rho = std::pow(1.0 - std::pow(std::abs(s), m), 1.0 / m);
  const double r =
      std::pow(std::pow(std::abs(c), m) + std::pow(std::abs(d), m), -1.0 / m);
  const Eigen::Vector3d u(s, rho * r * c, rho * r * d);
  const double x = kHalfLength * u(0);
  const double h = HalfHeight(x), dh = HalfHeightDerivative(x);
  const double w = HalfWidth(x), dw = HalfWidthDerivative(x);
  *point = Eigen::Vector3d(x, h * u(1) + h + kSoleY, w * u(2));
  Eigen::Matrix3d jacobian;
  jacobian << kHalfLength, 0.0, 0.0,            //
      kHalfLength * dh * (u(1) + 1.0), h, 0.0,  //
      kHalfLength * dw * u(2), 0.0, w;
  Eigen::Vector3d gradient;
  for (int i = 0; i < 3; ++i) gradient(i) = SignedPower(u(i), m - 1.0);
  *normal = jacobian.transpose().inverse() * gradient;
  normal->normalize();
}

// Surface coordinates (s, θ) of the shoe's points, edges first (evenly
// spaced along the long edges and the toe and heel loops), then six corners
// and random texture on the lateral side and top.
std::vector<Eigen::Vector2d> ShoeParameters(int num_points, Random* geometry) {
  const int num_texture =
      static_cast<int>(std::lround(num_points * 30.0 / 110.0));
  const int num_edge = num_points - num_texture;
  struct Edge {
    double s0, s1, theta0, theta1;
    int share;  // relative number of points
  };
  const double q = 0.25 * kPi;
  const double loop = 0.84;  // |s| of the toe and heel loops
  const Edge edges[] = {
      {-0.95, 0.95, -q, -q, 24},        // top-lateral long edge
      {-0.9, 0.9, -3 * q, -3 * q, 16},  // bottom-lateral long edge
      {-0.9, 0.9, q, q, 12},            // top-medial long edge
      {loop, loop, -3 * q, q, 14},      // toe loop, lateral side and top
      {-loop, -loop, -3 * q, q, 14},    // heel loop, lateral side and top
  };
  int share_sum = 0;
  for (const Edge& edge : edges) share_sum += edge.share;
  std::vector<Eigen::Vector2d> params;
  int assigned = 0;
  for (size_t i = 0; i < std::size(edges); ++i) {
    const int count = i + 1 == std::size(edges)
                          ? num_edge - assigned
                          : num_edge * edges[i].share / share_sum;
    assigned += count;
    for (int j = 0; j < count; ++j) {
      const double a = (j + 0.5) / count;
      params.emplace_back(
          edges[i].s0 + a * (edges[i].s1 - edges[i].s0),
          edges[i].theta0 + a * (edges[i].theta1 - edges[i].theta0));
    }
  }
  const Eigen::Vector2d corners[] = {{loop, -3 * q},  {loop, -q},  {loop, q},
                                     {-loop, -3 * q}, {-loop, -q}, {-loop, q}};
  for (int i = 0; i < num_texture; ++i) {
    if (i < static_cast<int>(std::size(corners))) {
      params.push_back(corners[i]);
    } else {
      const double s = geometry->Uniform(-0.9, 0.9);
      params.emplace_back(s, geometry->Uniform(-3 * q + 0.2, q - 0.2));
    }
  }
  return params;
}

}  // namespace synthetic
}  // namespace nrsfm
