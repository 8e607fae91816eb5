#include "solvers/triple_start.h"

#include <sstream>
#include <vector>

#include <glog/logging.h>

namespace nrsfm {

Status TripleStart(const Measurements& centered, int num_bases,
                   const AlternationOptions& options, std::uint64_t seed,
                   Model* model, TripleStartSummary* summary) {
  CHECK(model != nullptr && summary != nullptr);
  CHECK_EQ(centered.num_cameras, 1);
  NRSFM_RETURN_IF_ERROR(options.Check().WithContext("triple start"));
  const int f = centered.num_frames;
  const int p = centered.num_points;
  const int k = num_bases;
  if (k < 1 || 2 * f < 3 || p < 4) {
    std::ostringstream msg;
    msg << "triple start: needs K >= 1, 2F >= 3 and P >= 4; got K = " << k
        << ", F = " << f << ", P = " << p;
    return Status::Error(msg.str());
  }
  *summary = TripleStartSummary();
  std::vector<Eigen::Matrix3d> rotations;
  Eigen::VectorXd scales;
  Eigen::Matrix3Xd rigid_shape;
  NRSFM_RETURN_IF_ERROR(RotationsFromTriple(centered, k, seed, &rotations, &scales,
                                            &rigid_shape, &summary->triple)
                            .WithContext("triple start"));
  AlternateFromRigid(centered, k, rotations, scales, rigid_shape, options, seed,
                     /*update_rotations=*/false, model, &summary->alternation);
  return Status::OK();
}

}  // namespace nrsfm
