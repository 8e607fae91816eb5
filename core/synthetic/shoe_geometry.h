// The geometry of the synthetic shoe (core/synthetic/synthetic.h GenerateShoe):
// its surface and where its points lie on it. Object frame: x from heel −0.5 to
// toe +0.5, y up, the sole at y = kSoleY, z lateral (−) to medial (+); camera
// 0 at rest looks along +z at the lateral side, from above once pitched.
#ifndef NRSFM_CORE_SYNTHETIC_SHOE_GEOMETRY_H_
#define NRSFM_CORE_SYNTHETIC_SHOE_GEOMETRY_H_

#include <Eigen/Core>
#include <vector>

#include "core/math/random.h"

namespace nrsfm {
namespace synthetic {

inline constexpr double kShoeHalfLength = 0.5;
inline constexpr double kShoeSoleY = -0.11;

// Point and outward unit normal of the shoe at surface coordinates
// (s, theta): s ∈ (−1, 1) runs from heel to toe, theta is the direction of
// the point in the cross-section (0 = up, −π/2 = lateral). The surface is a
// superellipsoid (exponent 4) with a flat sole, a raised heel and a lower,
// tapered toe.
void ShoeSurface(double s, double theta, Eigen::Vector3d* point,
                 Eigen::Vector3d* normal);

// Surface coordinates (s, θ) of the shoe's `num_points` points, edges first
// (evenly spaced along the long edges and the toe and heel loops), then six
// corners and random texture on the lateral side and top (drawn from
// `geometry`).
std::vector<Eigen::Vector2d> ShoeParameters(int num_points, Random* geometry);

}  // namespace synthetic
}  // namespace nrsfm

#endif  // NRSFM_CORE_SYNTHETIC_SHOE_GEOMETRY_H_
