// Synthetic sequences with full ground truth: random basis shapes and the
// deforming superquadric (the synthetic experiments of Torresani et al.
// 2001), a shoe-style two-camera sequence with self-occlusion, and real 3-D
// ground truth re-projected under a chosen camera path (the robustness
// tests). One generator per file (core/synthetic/synthetic_random_basis.cc,
// core/synthetic/synthetic_superquadric.cc, core/synthetic/synthetic_shoe.cc
// with core/synthetic/shoe_geometry.h, core/synthetic/synthetic_reproject.cc;
// shared pieces in core/synthetic/synthetic_common.h).
//
// Every generator is seeded and deterministic: the same options give
// bit-identical output on any run of the same build (core/math/random.h). Each
// seed drives independent streams for geometry, motion, noise and missing
// entries, so changing `noise_stddev` or `missing_fraction` leaves the truth
// unchanged, and the noise of an entry does not depend on which entries are
// missing.
//
// Common to all generators: every basis shape is centred (zero mean over the
// points), so every S_t is centred; the weight of basis 1 is 1 in every frame
// (the rest / rigid shape); missing entries are NaN in W and false in the mask.
#ifndef NRSFM_CORE_SYNTHETIC_SYNTHETIC_H_
#define NRSFM_CORE_SYNTHETIC_SYNTHETIC_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "core/io/ground_truth.h"
#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"

namespace nrsfm {

// Measurements and the model that generated them. `truth.Project(t, c)` equals
// the noise-free measurements; `truth.ShapeInCamera(t, c)` is the 3D ground
// truth of frame t seen by camera c.
struct SyntheticSequence {
  Measurements measurements;
  Model truth;
};

// The frames, camera path, noise and missing entries of the random-basis and
// the superquadric sequences: rotations R_t = Rz(c_t) Ry(b_t) Rx(a_t) whose
// three angles follow smooth random curves (two random-phase sinusoids,
// ~0.5–3 cycles over the sequence) within ±max_rotation_deg / 2 (so the
// sequence spans up to max_rotation_deg about every axis; the same seed and F
// give the same rotations); zero translations; Gaussian noise of std
// `noise_stddev` (in the units of W) on every visible entry;
// round(missing_fraction · F · P) entries removed uniformly at random,
// skipping any removal that would leave a frame or a point with fewer than 2
// visible entries (so very high fractions are not always reached).
struct SmoothSequenceOptions {
  int num_frames = 300;            // F, >= 2
  double max_rotation_deg = 90.0;  // span of the rotation about each axis, deg
  double noise_stddev = 0.0;       // Gaussian noise on W (input units), >= 0
  double missing_fraction = 0.0;   // fraction of entries removed, [0, 1)
  std::uint64_t seed = 1;          // any value
};

// Random basis shapes (Torresani et al. 2001): points uniform in the unit cube
// [-0.5, 0.5]³ for every basis (then centred); weights l_t1 = 1 (first basis
// dominant, the rigid component) and l_tk ~ N(0, deformation²) i.i.d. for k >
// 1; camera path, noise and missing entries of SmoothSequenceOptions.
// Noise-free W has rank 3K when P ≥ 3K and F is large.
struct RandomBasisOptions : SmoothSequenceOptions {
  int num_points = 50;       // P, >= 1
  int num_bases = 5;         // K (of the generating model), >= 1
  double deformation = 0.3;  // std of l_tk, k > 1 (basis 1 weight is 1)

  // Errors name the field and value: F < 2, P < 1, K < 1, negative or
  // non-finite deformation or noise, rotation span outside [0, 360] deg,
  // missing fraction outside [0, 1).
  Status Check() const;
};
Status GenerateRandomBasis(const RandomBasisOptions& options,
                           SyntheticSequence* sequence);

// Superquadric (Torresani et al. 2001, Fig. 5c): P points on the surface
// |x/0.5|^(2/e) + |y/0.4|^(2/e) + |z/0.3|^(2/e) = 1, e = 0.5 (a rounded box),
// at random surface parameters. Three octants, (+,+,+), (−,−,+), (+,−,−),
// deform independently: mode o scales the points of octant o radially, faded
// smoothly to zero at the octant's three planes, with a smooth weight in
// [−0.5, 0.5]. Exact model, K = 4: basis 1 = the rest shape (weight 1), bases
// 2–4 = the octant modes. Camera path, noise and missing entries of
// SmoothSequenceOptions (the same as the random-basis data's for the same
// seed and F).
struct SuperquadricOptions : SmoothSequenceOptions {
  int num_points = 200;  // P, >= 1

  // Errors as for RandomBasisOptions.
  Status Check() const;
};
Status GenerateSuperquadric(const SuperquadricOptions& options,
                            SyntheticSequence* sequence);

// Shoe-style (after Torresani et al. 2001's deforming shoe). Object frame: x
// from heel (−0.5) to toe
// (+0.5), y up, z from the lateral (−) to the medial (+) side; length 1.
// Surface: a superellipsoid (exponent 4) with a flat sole, a raised heel and a
// lower, tapered toe. Points (110 by default): round(P · 30/110) on six
// corners and random texture on the lateral side and top, the rest evenly along
// the top-lateral, bottom-lateral and top-medial long edges and the toe and
// heel loops. Exact low-rank model, K = 4:
//   S_t = S_rest + a_t1 D_toe + a_t2 D_flex + a_t3 D_squash
// (weights (1, a_t1, a_t2, a_t3), smooth in t): D_toe = linearised rotation
// of the toe about the transverse axis through the ball of the foot, faded in
// smoothly over the toe, with a slight widening (a_t1 ∈ [0, 0.5] rad);
// D_flex = linearised bending of the whole shoe about the sole line, widening
// where it bends (a_t2 ∈ ±0.6); D_squash = vertical compression with a
// forward push and lateral bulge of the upper, strongest at the heel
// (a_t3 ∈ ±0.1). Every mode has three independent non-linear rows, so
// noise-free complete W has rank exactly 3K + 1 = 13 (+1: translations).
// Motion: R_t0 = Rx(pitch) Rz(roll) Ry(yaw), smooth; yaw about the vertical
// axis spans up to 120° (±60° around −baseline/2 with two cameras), pitch
// −28° ± 18° (the camera looks down at the shoe), roll ±20°; smooth
// translations up to ±0.2 per view.
// Cameras (`num_cameras` 1 or 2): camera 1 has R_t1 = Ry(camera_baseline_deg)
// R_t0 and scale s_t1 = 0.9 (camera 0: s = 1); the same values are in
// truth.rig_rotations (angle-axis (0, baseline, 0)) and truth.rig_scales.
// Self-occlusion (`self_occlusion`): each point has the outward normal n of
// the rest shape; the camera looks along +z, so the point is visible in view
// (t, c) iff (R_tc n)_z < 0 (deformation ignored); the share of entries it
// hides with the defaults is measured in docs/benchmark.md. Every view keeps
// at least 4 points and every point at least one observation (the most
// camera-facing ones are made visible when needed). Gaussian noise as in the
// random-basis data.
struct ShoeOptions {
  int num_frames = 500;               // F, >= 2
  int num_points = 110;               // P, >= 10
  int num_cameras = 2;                // M, 1 or 2
  double camera_baseline_deg = 30.0;  // camera 1 yaw, deg, [−90, 90]
  double noise_stddev = 0.0;          // Gaussian noise on W (input units), >= 0
  bool self_occlusion = true;         // hide points whose normal faces away
  std::uint64_t seed = 1;             // any value

  // Errors name the field and value (F < 2, P < 10, M not 1 or 2, baseline
  // outside [−90, 90], negative or non-finite noise).
  Status Check() const;
};
Status GenerateShoe(const ShoeOptions& options, SyntheticSequence* sequence);

// How the camera's angle θ_t grows over the frames (τ = t / (F − 1)):
enum class SpeedProfile {
  kConstant,   // θ_t = Θ τ: constant angular velocity
  kRamp,       // θ_t = Θ τ²: the speed grows linearly from rest
  kStopAndGo,  // eight equal segments, moving at constant speed and standing
               // still in turn (moving first); θ_t continuous
};
// "constant", "ramp", "stopgo"; the error lists them.
const char* SpeedProfileName(SpeedProfile profile);
Status ParseSpeedProfile(const std::string& name, SpeedProfile* profile);

// Re-projection of real 3-D ground truth (a motion-capture sequence) under a
// chosen orthographic camera path, for robustness tests: slow rotation,
// uneven speed, noise, missing data. The object frame of the source (its
// world-frame S when it has S + Rs, else its camera-frame points) is kept:
// S_t is the source's shape of frame t, unchanged. The camera of frame t is
//   R_t = Rot(axis, θ_t) R_0,   w_tp = Π R_t S_t[:, p] + noise,
// with R_0 the source's first camera (identity when it has none), `axis` a
// direction in R_0's camera frame ((0, 1, 0), the image's vertical, makes
// the camera orbit the object as the Akhter et al. sequences do) and θ_t
// from `profile`, θ_{F−1} = Θ = total_rotation_deg. The image size is the
// object's size in the image: the largest side of a frame's bounding box of
// the noise-free tracks, over the frames; noise is i.i.d.
// Gaussian of std noise_fraction · image size on every coordinate.
// Missing entries: first self-occlusion (occlusion_radius > 0): point p is
// hidden in frame t when another point lies within occlusion_radius · image
// size of it in the image and at least that much nearer the camera (a limb
// in front of it); then round(missing_fraction · F · P) entries removed at
// random. Neither leaves a frame or a point with fewer than 2 entries
// (occluded entries of such a point or frame are shown again, the least
// hidden first; random removals that would do it are skipped).
// A source without an object frame (P3_gt, X) gives its camera-frame shapes
// as the object frame: any rotation of the object in them is then motion of
// the object, which a reconstruction may explain as camera motion; compare
// such sequences in the camera frame (e3d_camera, frob_zsign).
struct ReprojectOptions {
  double total_rotation_deg = 90.0;  // Θ, degrees, (0, 3600]
  // non-zero, R_0's camera frame
  Eigen::Vector3d axis = Eigen::Vector3d::UnitY();
  SpeedProfile profile = SpeedProfile::kConstant;
  double noise_fraction = 0.0;  // noise std / image size, [0, 1)
  // fraction of entries removed at random, [0, 1)
  double missing_fraction = 0.0;
  // self-occlusion radius / image size, [0, 1); 0 = none
  double occlusion_radius = 0.0;
  std::uint64_t seed = 1;  // noise and random missing entries
  // 0: the orthographic camera above. > 0: a pinhole camera whose centre
  // is distance_ratio × the object's size (the largest side of the 3-D
  // bounding box of all its points) from the object's mean point, on its
  // optical axis: X_t = R_t S_t − R_t c̄ + (0, 0, D), w = (f x / z + 500,
  // f y / z + 500) pixels, f = kPinholeImagePixels · distance_ratio, so
  // the object spans about kPinholeImagePixels pixels at any ratio; the
  // measurements get these intrinsics and the truth the camera-frame X_t.
  // Errors when a point is not in front of the camera. [0, 1e6].
  double distance_ratio = 0.0;

  // Errors name the field and value.
  Status Check() const;
};

// The image size a pinhole re-projection aims at, pixels.
inline constexpr double kPinholeImagePixels = 500.0;

struct ReprojectedSequence {
  Measurements measurements;  // M = 1, W of 2F rows
  // The source's object-frame shapes with the new rotations R_t (camera
  // from object) and points_in_camera = R_t S_t (source "S+Rs").
  GroundTruth truth;
  double image_size = 0.0;    // input units
  double noise_stddev = 0.0;  // noise_fraction · image_size
};

// Errors on invalid options and on a source with fewer than 2 frames or 1
// point.
Status GenerateReprojection(const GroundTruth& source,
                            const ReprojectOptions& options,
                            ReprojectedSequence* sequence);

}  // namespace nrsfm

#endif  // NRSFM_CORE_SYNTHETIC_SYNTHETIC_H_
