#include <glog/logging.h>

#include "core/model/option_checker.h"
#include "core/synthetic/synthetic.h"
#include "core/synthetic/synthetic_common.h"

namespace nrsfm {

using synthetic::CentreBasis;
using synthetic::CheckSmoothSequence;
using synthetic::FinishSmoothSequence;
using synthetic::kGeometryStream;
using synthetic::kMotionStream;
using synthetic::SetSmoothRotations;

Status RandomBasisOptions::Check() const {
  OptionChecker check("RandomBasisOptions");
  CheckSmoothSequence(*this, &check);
  check.AtLeast("num_points", num_points, 1);
  check.AtLeast("num_bases", num_bases, 1);
  check.FiniteAtLeast("deformation", deformation, 0.0);
  return check.status();
}

Status GenerateRandomBasis(const RandomBasisOptions& options,
                           SyntheticSequence* sequence) {
  CHECK(sequence != nullptr);
  NRSFM_RETURN_IF_ERROR(options.Check());
  Random geometry(options.seed, kGeometryStream);
  Random motion(options.seed, kMotionStream);
  Model& truth = sequence->truth;
  truth.Resize(options.num_frames, 1, options.num_points, options.num_bases);
  for (int k = 0; k < options.num_bases; ++k) {
    Eigen::Matrix3Xd shape(3, options.num_points);
    for (int p = 0; p < options.num_points; ++p) {
      for (int i = 0; i < 3; ++i) shape(i, p) = geometry.Uniform(-0.5, 0.5);
    }
    truth.SetBasisShape(k, shape);
  }
  CentreBasis(&truth);
  SetSmoothRotations(options.max_rotation_deg, &motion, &truth);
  for (int t = 0; t < options.num_frames; ++t) {
    truth.weights(0, t) = 1.0;
    for (int k = 1; k < options.num_bases; ++k) {
      truth.weights(k, t) = options.deformation * motion.Normal();
    }
  }
  FinishSmoothSequence(options, sequence);
  return Status::OK();
}

}  // namespace nrsfm
