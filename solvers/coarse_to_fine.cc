#include "solvers/coarse_to_fine.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include <glog/logging.h>

#include "core/random.h"


namespace nrsfm {
namespace {

// `model` with one more basis shape: S_{K+1} = 0, weights stddev · N(0, 1).
Model AppendBasis(const Model& model, double stddev, Random* normal) {
  Model grown;
  grown.Resize(model.num_frames, model.num_cameras, model.num_points,
               model.num_bases + 1);
  grown.rotations = model.rotations;
  grown.translations = model.translations;
  grown.scales = model.scales;
  grown.rig_rotations = model.rig_rotations;
  grown.rig_scales = model.rig_scales;
  const int k = model.num_bases;
  grown.weights.topRows(k) = model.weights;
  for (int t = 0; t < model.num_frames; ++t) {
    grown.weights(k, t) = stddev * normal->NormalUnpaired();
  }
  grown.basis.topRows(3 * k) = model.basis;
  grown.basis.bottomRows(3).setZero();
  return grown;
}

Status RunOneStart(const ReconstructOptions& options,
                   const RobustReconstructOptions& robust,
                   const Measurements& measurements, ReconstructResult* result) {
  const int target = options.start.num_bases;
  const bool grow = robust.coarse_to_fine && robust.start_num_bases < target;
  ReconstructOptions coarse = options;
  if (grow) {
    coarse.start.num_bases = robust.start_num_bases;
    coarse.solver.max_iterations = robust.intermediate_max_iterations;
  }
  NRSFM_RETURN_IF_ERROR(Initialize(coarse.start, measurements, &result->model,
                                   &result->start));
  NRSFM_RETURN_IF_ERROR(Refine(coarse.problem, coarse.solver, measurements,
                               &result->model, &result->refine));
  if (!grow) return Status::OK();
  Random normal(robust.seed);
  for (int k = robust.start_num_bases + 1; k <= target; ++k) {
    const double weight_rms =
        std::sqrt(result->model.weights.squaredNorm() /
                  std::max<double>(1.0, result->model.weights.size()));
    Model grown =
        AppendBasis(result->model, robust.new_weight_stddev * weight_rms, &normal);
    const SolverOptions& solver = k == target ? options.solver : coarse.solver;
    RefineSummary summary;
    NRSFM_RETURN_IF_ERROR(
        Refine(options.problem, solver, measurements, &grown, &summary));
    VLOG(1) << "coarse-to-fine: K = " << k << " cost " << summary.final_cost
            << " rms " << summary.reprojection_rms;
    result->model = std::move(grown);
    result->refine = summary;
  }
  return Status::OK();
}

}  // namespace

Status RobustReconstructOptions::Check() const {
  if (start_num_bases < 1) {
    return Status::Error("robust reconstruct: start_num_bases must be >= 1, got " +
                         std::to_string(start_num_bases));
  }
  if (intermediate_max_iterations < 0) {
    return Status::Error(
        "robust reconstruct: intermediate_max_iterations must be >= 0, got " +
        std::to_string(intermediate_max_iterations));
  }
  if (!(new_weight_stddev > 0.0) || !std::isfinite(new_weight_stddev)) {
    return Status::Error(
        "robust reconstruct: new_weight_stddev must be positive and finite, got " +
        std::to_string(new_weight_stddev));
  }
  if (num_starts < 1) {
    return Status::Error("robust reconstruct: num_starts must be >= 1, got " +
                         std::to_string(num_starts));
  }
  return Status::OK();
}

Status RobustReconstruct(const ReconstructOptions& options,
                         const RobustReconstructOptions& robust,
                         const Measurements& measurements,
                         ReconstructResult* result,
                         RobustReconstructSummary* summary) {
  CHECK(result != nullptr);
  const auto start = std::chrono::steady_clock::now();
  NRSFM_RETURN_IF_ERROR(options.Check());
  NRSFM_RETURN_IF_ERROR(robust.Check());
  RobustReconstructSummary local;
  double best_cost = std::numeric_limits<double>::infinity();
  Status last_error = Status::OK();
  bool any = false;
  for (int i = 0; i < robust.num_starts; ++i) {
    ReconstructOptions start_options = options;
    if (i > 0) {
      start_options.start.method = StartMethod::kRigid;
      start_options.start.seed = options.start.seed + static_cast<std::uint64_t>(i);
    }
    ReconstructResult candidate;
    const Status status = RunOneStart(start_options, robust, measurements, &candidate);
    if (!status.ok()) {
      last_error = status;
      local.start_final_costs.push_back(std::nan(""));
      continue;
    }
    const double cost = candidate.refine.usable
                            ? candidate.refine.final_cost
                            : std::numeric_limits<double>::infinity();
    local.start_final_costs.push_back(cost);
    if (!any || cost < best_cost) {
      best_cost = cost;
      local.best_start = i;
      *result = std::move(candidate);
      any = true;
    }
  }
  if (!any) return last_error;
  result->total_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  if (summary != nullptr) *summary = local;
  return Status::OK();
}

}  // namespace nrsfm
