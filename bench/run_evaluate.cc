#include "bench/run_evaluate.h"

#include <utility>

namespace nrsfm {
namespace bench {

Status Evaluate(const Model& model, const GroundTruth& truth,
                ShapeErrors* errors) {
  return EvaluateShapes(truth, ShapesOfModel(model, 0), errors);
}

RunOutcome ReconstructAndEvaluate(const ReconstructOptions& options,
                                  const Measurements& measurements,
                                  const GroundTruth& truth) {
  RunOutcome outcome;
  ReconstructResult result;
  const Status status = Reconstruct(options, measurements, &result);
  if (!status.ok()) {
    outcome.message = status.message();
    return outcome;
  }
  outcome.start = StartMethodName(result.start.method);
  outcome.init_seconds = result.start.seconds;
  outcome.refine_seconds = result.refine.seconds;
  outcome.total_seconds = result.total_seconds;
  outcome.iterations = result.refine.iterations;
  outcome.seconds_per_iteration =
      result.refine.iterations > 0
          ? (result.refine.minimizer_seconds - result.refine.callback_seconds) /
                result.refine.iterations
          : 0.0;
  outcome.reprojection_rms = result.refine.usable
                                 ? result.refine.reprojection_rms
                                 : result.start.reprojection_rms;
  outcome.linear_solver = result.refine.linear_solver;
  outcome.converged = result.refine.converged;
  outcome.warnings = result.start.warnings;
  outcome.warnings.insert(outcome.warnings.end(), result.warnings.begin(),
                          result.warnings.end());
  if (!result.refine.usable) {
    outcome.message = "refinement not usable: " + result.refine.message;
  }
  const Status eval = Evaluate(result.model, truth, &outcome.errors);
  if (!eval.ok()) {
    outcome.message = eval.message();
    return outcome;
  }
  outcome.ok = result.refine.usable;
  outcome.model = std::move(result.model);
  return outcome;
}

GroundTruth TruthShapes(const Model& truth) {
  GroundTruth shapes;
  shapes.points_in_camera = CameraFrameShapes(truth, 0);
  shapes.source = "model";
  return shapes;
}

}  // namespace bench
}  // namespace nrsfm
