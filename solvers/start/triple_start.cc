#include "solvers/start/triple_start.h"

#include <glog/logging.h>

#include <vector>

namespace nrsfm {

Status TripleStart(const Measurements& centered, int num_bases,
                   const AlternationOptions& options, std::uint64_t seed,
                   int num_threads, Model* model, TripleStartSummary* summary) {
  CHECK(model != nullptr && summary != nullptr);
  NRSFM_RETURN_IF_ERROR(CheckAlternationInput(centered, num_bases, options)
                            .WithContext("triple start"));
  const int k = num_bases;
  *summary = TripleStartSummary();
  std::vector<Eigen::Matrix3d> rotations;
  Eigen::VectorXd scales;
  Eigen::Matrix3Xd rigid_shape;
  NRSFM_RETURN_IF_ERROR(RotationsFromTriple(centered, k, seed, num_threads,
                                            &rotations, &scales, &rigid_shape,
                                            &summary->triple)
                            .WithContext("triple start"));
  AlternateFromRigid(centered, k, rotations, scales, rigid_shape, options, seed,
                     /*update_rotations=*/false, model, &summary->alternation,
                     num_threads);
  return Status::OK();
}

}  // namespace nrsfm
