// One reconstruction of the nrsfm_bench suites scored against ground truth
// (camera 0): Reconstruct() + core/eval/metrics.h, never failing (problems go
// into the outcome's message).
#ifndef NRSFM_BENCH_RUN_EVALUATE_H_
#define NRSFM_BENCH_RUN_EVALUATE_H_

#include <string>
#include <vector>

#include "core/eval/metrics.h"
#include "core/io/ground_truth.h"
#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"
#include "solvers/pipeline/reconstruct.h"

namespace nrsfm {
namespace bench {

// One reconstruction scored against camera-0 ground truth.
struct RunOutcome {
  bool ok = false;      // Reconstruct() succeeded and the refinement is usable
  std::string message;  // why not
  ShapeErrors errors;   // core/eval/metrics.h
  std::string start;    // StartMethodName of the start kept
  double init_seconds = 0;
  double refine_seconds = 0;
  double total_seconds = 0;
  int iterations = 0;  // LM iterations
  // The solver's own minimizer time / iterations: without the time in the
  // callbacks, where auto's two starts wait for each other.
  double seconds_per_iteration = 0;
  double reprojection_rms = 0;  // refined, input units
  std::string linear_solver;
  bool converged = false;             // the refinement ended by a tolerance
  std::vector<std::string> warnings;  // the start's and the result's
  Model model;                        // the reconstruction
};

// Scores `model` (camera 0) against `truth` (core/eval/metrics.h
// EvaluateShapes: the object frame when the truth has one).
Status Evaluate(const Model& model, const GroundTruth& truth,
                ShapeErrors* errors);

// Reconstruct() + Evaluate(). Never fails: problems go into outcome.message.
RunOutcome ReconstructAndEvaluate(const ReconstructOptions& options,
                                  const Measurements& measurements,
                                  const GroundTruth& truth);

// Camera-0 ground truth of a synthetic model (ShapeInCamera(t, 0)).
GroundTruth TruthShapes(const Model& truth);

}  // namespace bench
}  // namespace nrsfm

#endif  // NRSFM_BENCH_RUN_EVALUATE_H_
