// The one Ceres problem of a reconstruction (docs/problem.md).
//
// ProblemBuilder owns a ceres::Problem whose parameter blocks are the storage
// of a Model (core/model/model.h), so solving the problem updates the model in
// place. AddReprojectionTerms() adds the data term; the extra terms are
// added by AddExtraTerms (problems/extra_terms.h) through AddResidualBlock()
// and the block accessors below — the builder does not need to know them.
// The builder, not the problem, owns every cost function (the problem's
// per-function reference count is a std::map entry per block, 5.7 M of
// them on F 300 × P 10 000 with the temporal prior); a block added to
// problem() directly must come with a cost function its caller keeps alive.
//
// Parameter blocks (pointers into the model; sizes in brackets):
// clang-format off
//   RotationBlock(t, c)     ω_tc, angle-axis, radians       [3]   rotations.col(View(t, c))
//   TranslationBlock(t, c)  T_tc, input units               [2]   translations.col(View(t, c))
//   WeightsBlock(t)         l_t                             [K]   weights.col(t)
//   BasisBlock(p)           b_p = [S_1[:,p]; …; S_K[:,p]]   [3K]  basis.col(p)
//   ScaleBlock(t, c)        s_tc, c ≥ 1 of multi-camera     [1]   scales(View(t, c))
//                           data only; camera 0 has s = 1 and no block,
//                           monocular data have no scale block at all.
//   DepthBlock(t, c)        t_z,tc, perspective only:        [1]   depths(View(t, c))
//                           the data term of a perspective model
//                           (problems/perspective_error.h) uses it instead of
//                           s_tc; the first view's is held (the scale gauge).
// clang-format on
// A block is in the problem only once a residual uses it (a view that sees no
// point has no rotation block; test with problem()->HasParameterBlock).
//
// The gauges of docs/model.md (global rotation, K × K mixing, depth
// reflection, basis shift absorbed by the translations) leave every residual
// unchanged, so the Jacobian is rank-deficient. Nothing is held constant to
// fix them: Levenberg–Marquardt damping keeps each step finite and the solver
// converges along the other directions.
#ifndef NRSFM_PROBLEMS_PROBLEM_BUILDER_H_
#define NRSFM_PROBLEMS_PROBLEM_BUILDER_H_

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/problem.h>

#include <Eigen/Core>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"
#include "problems/problem_options.h"
#include "problems/rotation_manifold.h"

namespace nrsfm {

// The reprojection cost function for K bases. Hand-written Jacobian
// (problems/reprojection_cost_function.h): K = 1…kMaxStaticBases dispatch to
// a compile-time K (the one switch on K, in the .cc), larger K use a run-time
// K. `with_scale` adds the scale block; `sqrt_weight` = sqrt(w_obs).
std::unique_ptr<ceres::CostFunction> CreateReprojectionCostFunction(
    int num_bases, bool with_scale, const Eigen::Vector2d& observation,
    double sqrt_weight);

class ProblemBuilder {
 public:
  // `measurements` and `model` must outlive the builder; the model's storage
  // becomes the parameter blocks.
  ProblemBuilder(const Measurements* measurements, Model* model);
  ProblemBuilder(const ProblemBuilder&) = delete;
  ProblemBuilder& operator=(const ProblemBuilder&) = delete;

  // The checks AddReprojectionTerms makes of the data before it adds
  // anything: valid options, measurements and model, their sizes, camera 0's
  // scale 1, the observation_weights' size.
  static Status CheckInputs(const ProblemOptions& options,
                            const Measurements& measurements,
                            const Model& model);

  // Adds one residual block of 2 residuals per visible (t, c, p) with
  // w_obs > 0 (weak perspective or pinhole as the model's camera says) and
  // applies the constant flags to the blocks it added. Fails
  // (and adds nothing) on invalid options, measurements or model, on sizes
  // of model and measurements that differ, on a camera-0 scale other than 1,
  // or on an observation_weights matrix of the wrong size. Call once.
  Status AddReprojectionTerms(const ProblemOptions& options);

  // Keeps `cost` alive as long as the problem; returns it, for blocks that
  // share it (a cost function without per-block data).
  ceres::CostFunction* Own(std::unique_ptr<ceres::CostFunction> cost);
  // problem()->AddResidualBlock with a cost function the builder owns from
  // now on (`loss` stays the caller's, as with problem()).
  ceres::ResidualBlockId AddResidualBlock(
      std::unique_ptr<ceres::CostFunction> cost, ceres::LossFunction* loss,
      const std::vector<double*>& blocks);

  // Holds constant, of the blocks the problem has, every kind that
  // `options` marks constant (problems/problem_options.h).
  void SetConstantBlocks(const ProblemOptions& options);

  ceres::Problem* problem() { return &problem_; }
  const Measurements& measurements() const { return *measurements_; }
  Model* model() { return model_; }

  double* RotationBlock(int frame, int camera);
  double* TranslationBlock(int frame, int camera);
  double* WeightsBlock(int frame);
  double* BasisBlock(int point);
  double* DepthBlock(int frame, int camera);
  double* ScaleBlock(int frame, int camera);  // CHECKs camera ≥ 1
  // Rig blocks of camera c ≥ 1 (rigidity term, problems/rigidity_error.h):
  // ω_rig_c [3] = rig_rotations.col(c − 1), s_rig_c [1] = rig_scales(c − 1).
  double* RigRotationBlock(int camera);  // CHECKs 1 ≤ camera < M
  double* RigScaleBlock(int camera);     // CHECKs 1 ≤ camera < M

  // The blocks of the problem in two sets for the linear solver ordering:
  // point blocks (basis columns, point order) and every other block (per
  // view, per frame or shared). Only blocks present in the problem are
  // listed.
  std::vector<double*> PointBlocks();
  std::vector<double*> NonPointBlocks();
  // NonPointBlocks() split into groups whose order does not depend on where
  // the model's arrays lie in memory (Ceres orders the blocks of one
  // ordering group by address): rotations, translations, weights, scales,
  // depths, then every remaining block (added by other terms) in a group of its
  // own, in the order it was added. Empty groups are left out.
  std::vector<std::vector<double*>> NonPointBlockGroups();
  // True when no residual block of the problem uses two point blocks (the
  // point blocks are an independent set and can be Schur-eliminated).
  // O(number of residual blocks).
  bool PointBlocksAreIndependent() const;

  // Gives the rotation block `block` (already in the problem) the
  // multiplicative update of problems/rotation_manifold.h.
  // AddReprojectionTerms does it for every ω_tc; a term that adds other
  // rotation blocks (the rig's) calls it for them.
  void SetRotationManifold(double* block);

  // Number of reprojection residual blocks added.
  int num_reprojection_terms() const { return num_reprojection_terms_; }

 private:
  ceres::LossFunction* LossForWeight(const ProblemOptions& options,
                                     double weight);

  const Measurements* measurements_;
  Model* model_;
  // Losses are shared between residual blocks of equal weight and owned here
  // (declared before problem_ so they outlive it).
  std::map<double, std::unique_ptr<ceres::LossFunction>> losses_;
  AngleAxisManifold rotation_manifold_;  // shared by every rotation block
  // Declared before problem_, so destroyed after it.
  std::vector<std::unique_ptr<ceres::CostFunction>> cost_functions_;
  ceres::Problem problem_;
  int num_reprojection_terms_ = 0;
};

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_PROBLEM_BUILDER_H_
