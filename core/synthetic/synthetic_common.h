// Pieces shared by the synthetic generators (core/synthetic/synthetic.h: the
// random basis, superquadric, shoe and re-projected sequences, one file each);
// not part of the library's API.
#ifndef NRSFM_CORE_SYNTHETIC_SYNTHETIC_COMMON_H_
#define NRSFM_CORE_SYNTHETIC_SYNTHETIC_COMMON_H_

#include <Eigen/Core>
#include <cmath>
#include <cstdint>

#include "core/math/random.h"
#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/option_checker.h"
#include "core/synthetic/synthetic.h"

namespace nrsfm {
namespace synthetic {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kDegToRad = kPi / 180.0;

// Independent random streams of one seed: changing the noise or the missing
// fraction leaves the geometry and motion of a sequence unchanged.
enum Stream : std::uint64_t {
  kGeometryStream = 1,
  kMotionStream = 2,
  kNoiseStream = 3,
  kMissingStream = 4,
};

// A smooth signal in [−1, 1] over tau ∈ [0, 1]: two sinusoids of random phase
// with `min_cycles`…`max_cycles` and 1…2 times that many cycles.
struct SmoothCurve {
  double cycles1, cycles2, phase1, phase2;
  double operator()(double tau) const {
    return 0.6 * std::sin(2.0 * kPi * cycles1 * tau + phase1) +
           0.4 * std::sin(2.0 * kPi * cycles2 * tau + phase2);
  }
};
SmoothCurve RandomCurve(Random* random, double min_cycles, double max_cycles);

// τ = t / (F − 1) ∈ [0, 1].
double Tau(int frame, int num_frames);

// Rotation by `angle` (radians) about axis 0 (x), 1 (y) or 2 (z).
Eigen::Matrix3d AxisRotation(int axis, double angle);

// Hermite smooth step from 0 at edge0 to 1 at edge1, and its derivative.
double SmoothStep(double edge0, double edge1, double x);
double SmoothStepDerivative(double edge0, double edge1, double x);

// sign(c)·|c|^e: the signed power of the superquadric parametrisation.
double SignedPower(double c, double e);

// R_t = Rz(c_t) Ry(b_t) Rx(a_t), each angle max_rotation_deg / 2 · curve(τ):
// the rotations shared by the random-basis and superquadric data.
void SetSmoothRotations(double max_rotation_deg, Random* motion, Model* truth);

// Subtracts from every basis shape its mean over the points, so every S_t is
// centred and, with zero translations, so is every complete frame of W.
void CentreBasis(Model* truth);

// All visible, then `fraction` of the entries removed in random order, skipping
// any removal that would leave a view or a point with fewer than 2 entries.
VisibilityMask RandomMissing(int num_views, int num_points, double fraction,
                             Random* random);
// The same on an existing mask: round(fraction · size) more entries hidden
// (already hidden ones are passed over), with the same rule.
void RemoveAtRandom(double fraction, Random* random, VisibilityMask* visible);

// W = truth.Project(t, c) plus N(0, noise²) on the visible entries (drawn
// from the noise stream of `seed`), NaN on the others.
void FillMeasurements(const Model& truth, const VisibilityMask& visible,
                      double noise_stddev, std::uint64_t seed,
                      Measurements* measurements);

// The rules of the SmoothSequenceOptions fields (F ≥ 2, rotation span in
// [0, 360] deg, noise finite and ≥ 0, missing fraction in [0, 1)), added to
// the generator's `check`.
void CheckSmoothSequence(const SmoothSequenceOptions& options,
                         OptionChecker* check);

// The last step of the random-basis and superquadric generators: the
// measurements of sequence->truth with the missing entries (RandomMissing,
// the missing stream of the seed) and the noise of `options`.
void FinishSmoothSequence(const SmoothSequenceOptions& options,
                          SyntheticSequence* sequence);

}  // namespace synthetic
}  // namespace nrsfm

#endif  // NRSFM_CORE_SYNTHETIC_SYNTHETIC_COMMON_H_
