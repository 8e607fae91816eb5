// The steps of `nrsfm reconstruct` and `nrsfm evaluate` that the tool
// (tools/commands.h), the Python module (python/) and the MATLAB function
// (matlab/) share, so that all run the same code and give the same results
// and the same error messages: observation weights and measurements from
// arrays, the reconstruction with a fixed K or --K auto, result.json's
// report and evaluate's line. Nothing here prints or touches gflags;
// library target nrsfm_tools.
#ifndef NRSFM_TOOLS_RECONSTRUCTION_STEPS_H_
#define NRSFM_TOOLS_RECONSTRUCTION_STEPS_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/eval/metrics.h"
#include "core/io/ground_truth.h"
#include "core/io/result_writer.h"
#include "core/model/measurements.h"
#include "core/model/status.h"
#include "solvers/pipeline/reconstruct.h"
#include "solvers/pipeline/result_uncertainty.h"
#include "solvers/pipeline/select_num_bases.h"
#include "tools/command_flags.h"

namespace nrsfm {
namespace tools {

// "nrsfm <version> (Ceres <version>, Eigen <version>)".
const char* VersionString();

// ProblemOptions::observation_weights from relative weights `given`, (F·M)
// × P like measurements.visible: a keypoint input's confidence
// (--confidence_weights) or the weights a Python or MATLAB caller gives.
// They are scaled to average 1 over the visible observations, so that equal
// weights give the unweighted reconstruction and the extra terms' λ keep
// their balance with the data term; entries that are not visible are 0
// (whatever `given` holds there, NaN too). Errors, naming `name`, on another
// size, a visible entry that is negative or not finite, and when every
// visible entry is 0.
Status RelativeObservationWeights(const Eigen::ArrayXXd& given,
                                  const Measurements& measurements,
                                  const std::string& name,
                                  Eigen::ArrayXXd* weights);

// Measurements from a W given in memory (2FM × P, NaN = missing) and a
// visibility mask (FM × P or 2FM × P, nonzero = visible; empty = none), as
// the Python module and the MATLAB function take them; `cameras` = M ≥ 1.
// Errors name "W" and "mask" (e.g. "W: only one coordinate of …").
Status MeasurementsFromArrays(const Eigen::MatrixXd& w,
                              const Eigen::MatrixXd& mask, int cameras,
                              Measurements* measurements);

// The rest of the options of a reconstruction of arrays (the Python module's
// reconstruct() and the MATLAB function), after ApplyFlags and
// MeasurementsFromArrays: CheckTermCameras
// (naming "W") and, from `observation_weights` (empty = none),
// ProblemOptions::observation_weights (RelativeObservationWeights, naming
// "observation_weights"); flags->confidence_weights is set to whether there
// are weights, so that the report's options say so.
Status ArrayReconstructOptions(const Measurements& measurements,
                               const Eigen::ArrayXXd& observation_weights,
                               CommandFlags* flags, FlagTargets* targets);

// After the input is read: every term given a weight has the cameras it
// needs (ExtraTerm::CheckCameras); the error names `input` and the flag,
// e.g. "s.mat: --rigidity: needs data from M >= 2 synchronised cameras, got
// M = 1".
Status CheckTermCameras(const CommandFlags& flags, const std::string& input,
                        int num_cameras);

// Ground truth from a .mat file (core/io/ground_truth.h) or a result directory
// (its points_camera.csv, camera 0), as --truth reads it.
Status ReadTruth(const std::string& path, const std::string& variable,
                 GroundTruth* truth);

// A reconstruction as `nrsfm reconstruct` runs it: --K N, or --K auto with
// --K_max and --K_threshold (solvers/pipeline/select_num_bases.h).
struct ReconstructionRun {
  bool auto_k = false;
  int num_bases = 0;               // K used (chosen, with auto)
  SelectNumBasesResult selection;  // with auto: the curve and noise estimate
  ReconstructResult result;
  // --uncertainty: its status (an error is a warning of the result, not of
  // the run), the covariances and their summary when it is OK.
  bool uncertainty_requested = false;
  Status uncertainty_status;
  Uncertainty uncertainty;
  UncertaintySummary uncertainty_summary;
};

// Runs it on `measurements` with the options of `targets` (ApplyFlags; the
// solver's progress / stop_requested are used as given); an error when --K
// was not given. `context` prefixes
// the errors of a fixed K (the tool: the input path).
// With observation weights, an error when a K to be run would leave points
// or frames out (solvers/pipeline/drop_unobserved.h): Reconstruct() passes the
// weights of all the measurements on to the ones it keeps, whose sizes
// differ, so such a run cannot be done yet; the error names what would be
// left out.
Status RunReconstruction(const FlagTargets& targets,
                         const Measurements& measurements,
                         const std::string& context, ReconstructionRun* run);

// result.json's report of `run` (input path, options, stages, warnings,
// the left-out points and frames, terms, diagnostics, versions); with
// `errors` (not null) its metrics too.
ReconstructionReport MakeReport(const CommandFlags& flags,
                                const std::string& input,
                                const ReconstructionRun& run,
                                const ShapeErrors* errors);

// The one JSON line `nrsfm evaluate` prints: MetricList, e3d_frame, F, P
// and, when not empty, unscored_frames / unscored_points.
// With num_bases > 0 and rank_floor ≥ 0 also "K" and "rank_floor"
// (ComputeRankFloorE3D of the object-frame truth).
std::string EvaluationJson(const ShapeErrors& errors, int num_bases = 0,
                           double rank_floor = -1.0);

}  // namespace tools
}  // namespace nrsfm

#endif  // NRSFM_TOOLS_RECONSTRUCTION_STEPS_H_
