#include <glog/logging.h>

#include <cmath>

#include "core/model/option_checker.h"
#include "core/synthetic/synthetic.h"
#include "core/synthetic/synthetic_common.h"

namespace nrsfm {

using synthetic::CentreBasis;
using synthetic::CheckSmoothSequence;
using synthetic::FinishSmoothSequence;
using synthetic::kGeometryStream;
using synthetic::kMotionStream;
using synthetic::kPi;
using synthetic::RandomCurve;
using synthetic::SetSmoothRotations;
using synthetic::SignedPower;
using synthetic::SmoothCurve;
using synthetic::SmoothStep;
using synthetic::Tau;

Status SuperquadricOptions::Check() const {
  OptionChecker check("SuperquadricOptions");
  CheckSmoothSequence(*this, &check);
  check.AtLeast("num_points", num_points, 1);
  return check.status();
}

Status GenerateSuperquadric(const SuperquadricOptions& options,
                            SyntheticSequence* sequence) {
  CHECK(sequence != nullptr);
  NRSFM_RETURN_IF_ERROR(options.Check());
  constexpr double kSemiAxes[3] = {0.5, 0.4, 0.3};
  constexpr double kExponent = 0.5;
  // The deforming octants (signs of x, y, z).
  constexpr double kOctants[3][3] = {{1, 1, 1}, {-1, -1, 1}, {1, -1, -1}};
  Random geometry(options.seed, kGeometryStream);
  Random motion(options.seed, kMotionStream);
  Model& truth = sequence->truth;
  truth.Resize(options.num_frames, 1, options.num_points, 4);
  Eigen::Matrix3Xd rest(3, options.num_points);
  for (int p = 0; p < options.num_points; ++p) {
    // asin of a uniform: area-uniform on a sphere, roughly so on the surface.
    const double eta = std::asin(geometry.Uniform(-1.0, 1.0));
    const double omega = geometry.Uniform(-kPi, kPi);
    const double c = SignedPower(std::cos(eta), kExponent);
    rest.col(p) << kSemiAxes[0] * c * SignedPower(std::cos(omega), kExponent),
        kSemiAxes[1] * c * SignedPower(std::sin(omega), kExponent),
        kSemiAxes[2] * SignedPower(std::sin(eta), kExponent);
  }
  truth.SetBasisShape(0, rest);
  for (int o = 0; o < 3; ++o) {
    // Radial scaling of the octant, faded smoothly to 0 at its three planes.
    Eigen::Matrix3Xd mode(3, options.num_points);
    for (int p = 0; p < options.num_points; ++p) {
      double falloff = 1.0;
      for (int i = 0; i < 3; ++i) {
        falloff *=
            SmoothStep(0.0, 0.5, kOctants[o][i] * rest(i, p) / kSemiAxes[i]);
      }
      mode.col(p) = falloff * rest.col(p);
    }
    truth.SetBasisShape(o + 1, mode);
  }
  CentreBasis(&truth);
  SetSmoothRotations(options.max_rotation_deg, &motion, &truth);
  for (int o = 0; o < 3; ++o) {
    const SmoothCurve curve = RandomCurve(&motion, 1.0, 3.0);
    for (int t = 0; t < options.num_frames; ++t) {
      truth.weights(0, t) = 1.0;
      truth.weights(o + 1, t) = 0.5 * curve(Tau(t, options.num_frames));
    }
  }
  FinishSmoothSequence(options, sequence);
  return Status::OK();
}

}  // namespace nrsfm
