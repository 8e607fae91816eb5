// The flags of tools/command_flags.h turned into the library's options, and
// the steps of the commands that the nrsfm tool (tools/commands.h) and the
// Python module (python/nrsfm_module.cc) share, so that both run the same
// code and give the same results and the same error messages. Nothing here
// prints or touches gflags; library target nrsfm_tools.
#ifndef NRSFM_TOOLS_FLAG_OPTIONS_H_
#define NRSFM_TOOLS_FLAG_OPTIONS_H_

#include <set>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/ground_truth.h"
#include "core/mat_io.h"
#include "core/measurements.h"
#include "core/metrics.h"
#include "core/read_measurements.h"
#include "core/result_writer.h"
#include "core/status.h"
#include "core/synthetic.h"
#include "problems/extra_terms.h"
#include "solvers/reconstruct.h"
#include "solvers/select_num_bases.h"
#include "tools/command_flags.h"

namespace nrsfm {
namespace tools {

// "nrsfm <version> (Ceres <version>, Eigen <version>)".
const char* VersionString();

// The commands a flag serves, from the start of its help text in
// NRSFM_COMMAND_FLAGS ("reconstruct, view: …; synth: …"): the help of
// `command` with the command names taken off (several parts joined by
// "; "), or "" when the flag does not serve `command`. A qualifier after
// the command name is kept: "reconstruct --K auto: largest K tried." gives
// "(--K auto) largest K tried." for "reconstruct".
std::string FlagHelpFor(const std::string& help, const std::string& command);

// The help of an extra term's weight flag (--smoothness, …): "reconstruct:
// weight of the <meaning>; <units>, 0 = off (docs/problem.md)."
std::string TermFlagHelp(const ExtraTerm& term);

// Parses --K of reconstruct: an integer >= 1 or "auto".
Status ParseNumBasesFlag(const std::string& value, bool* auto_k, int* num_bases);

// Sets ProblemOptions::constant_* from --hold's comma list of block kinds
// (rotations, translations, weights, basis, scales, rig); an unknown name is
// an error naming it.
Status ParseHeldBlocks(const std::string& list, ProblemOptions* options);

// Every reconstruct flag that sets a library option (--init, --priors,
// --robust, --robust_scale, --linear_solver, --max_iterations, --threads,
// --seed and the extra terms' weights; with --K auto it checks --K_max and
// --K_threshold, which RunReconstruction reads). The library's Check()
// judges every value; its errors come under the flag's name, e.g.
// "--K_max: K selection: max_num_bases must be >= 2, got 1".
Status BuildReconstructOptions(const CommandFlags& flags, ReconstructOptions* options);

// The flags that say how --input is read: --var, --mask_var, --format,
// --cameras and the keypoint inputs' --frame_key, --part, --min_confidence
// (the keywords of the Python module's read()).
const std::set<std::string>& InputFlags();

// Those flags as InputOptions; errors, under the flag's name, on an unknown
// --format or --part and a bad --frame_key or --min_confidence.
Status BuildInputOptions(const CommandFlags& flags, InputOptions* input);

// ProblemOptions::observation_weights from relative weights `given`, (F·M)
// × P like measurements.visible: a keypoint input's confidence
// (--confidence_weights) or the weights a Python or MATLAB caller gives.
// They are scaled to average 1 over the visible observations, so that equal
// weights give the unweighted reconstruction and the extra terms' λ keep
// their balance with the data term; entries that are not visible are 0
// (whatever `given` holds there, NaN too). Errors, naming `name`, on another
// size, a visible entry that is negative or not finite, and when every
// visible entry is 0.
Status RelativeObservationWeights(const Eigen::ArrayXXd& given, const Measurements& measurements,
                                  const std::string& name, Eigen::ArrayXXd* weights);

// Measurements from a W given in memory (2FM × P, NaN = missing) and a
// visibility mask (FM × P or 2FM × P, nonzero = visible; empty = none), as
// the Python module and the MATLAB function take them; `cameras` = M ≥ 1.
// Errors name "W" and "mask" (e.g. "W: only one coordinate of …").
Status MeasurementsFromArrays(const Eigen::MatrixXd& w, const Eigen::MatrixXd& mask, int cameras,
                              Measurements* measurements);

// The flags of reconstruct that are not options of a reconstruction of
// arrays (the Python module's reconstruct() and the MATLAB function): the
// tool's own (ToolOnlyFlags), how a file is read (InputFlags; cameras is an
// argument there), K (an argument) and confidence_weights (the caller gives
// observation weights instead).
std::set<std::string> NotArrayReconstructFlags();

// The rest of the options of a reconstruction of arrays, after
// BuildReconstructOptions and MeasurementsFromArrays: CheckTermCameras
// (naming "W") and, from `observation_weights` (empty = none),
// ProblemOptions::observation_weights (RelativeObservationWeights, naming
// "observation_weights"); flags->confidence_weights is set to whether there
// are weights, so that the report's options say so.
Status ArrayReconstructOptions(const Measurements& measurements,
                               const Eigen::ArrayXXd& observation_weights, CommandFlags* flags,
                               ReconstructOptions* options);

// Sets the flag `name` of `flags` (a member of NRSFM_COMMAND_FLAGS or an
// extra term) from `text` as the command line would give it: an integer,
// a number, "true"/"false" (or "1"/"0") or any string, by the flag's type.
// Errors name the flag and the value; an unknown name is an error too.
Status SetFlagFromText(const std::string& name, const std::string& text, CommandFlags* flags);

// After the input is read: every term given a weight has the cameras it
// needs (ExtraTerm::CheckCameras); the error names `input` and the flag,
// e.g. "s.mat: --rigidity: needs data from M >= 2 synchronised cameras, got
// M = 1".
Status CheckTermCameras(const CommandFlags& flags, const std::string& input,
                        int num_cameras);

// Ground truth from a .mat file (core/ground_truth.h) or a result directory
// (its points_camera.csv, camera 0), as --truth reads it.
Status ReadTruth(const std::string& path, const std::string& variable, GroundTruth* truth);

// A reconstruction as `nrsfm reconstruct` runs it: --K N, or --K auto with
// --K_max and --K_threshold (solvers/select_num_bases.h).
struct ReconstructionRun {
  bool auto_k = false;
  int num_bases = 0;              // K used (chosen, with auto)
  SelectNumBasesResult selection;  // with auto: the curve and noise estimate
  ReconstructResult result;
};

// Runs it on `measurements` with `options` (BuildReconstructOptions; its
// solver.progress / stop_requested are used as given). `context` prefixes
// the errors of a fixed K (the tool: the input path).
// With observation weights, an error when a K to be run would leave points
// or frames out (solvers/drop_unobserved.h): Reconstruct() passes the
// weights of all the measurements on to the ones it keeps, whose sizes
// differ, so such a run cannot be done yet; the error names what would be
// left out.
Status RunReconstruction(const CommandFlags& flags, const ReconstructOptions& options,
                         const Measurements& measurements, const std::string& context,
                         ReconstructionRun* run);

// The flags about the tool's own files and printing (input, output,
// overwrite, ply, quiet, truth, truth_var, result): not options of a
// reconstruction, so neither in result.json's "options" nor keywords of the
// Python module.
const std::set<std::string>& ToolOnlyFlags();

// The flags a reconstruction used, as result.json's "options": K (the K
// used) and K_flag (as given), every other flag of NRSFM_COMMAND_FLAGS that
// serves reconstruct and is not in ToolOnlyFlags() (in that list's order,
// as given: `cameras` 0 = from the file), then the extra terms' weights.
std::vector<std::pair<std::string, std::string>> OptionList(const CommandFlags& flags,
                                                            int num_bases);

// result.json's report of `run` (input path, options, stages, warnings,
// the left-out points and frames, terms, diagnostics, versions); with
// `errors` (not null) its metrics too.
ReconstructionReport MakeReport(const CommandFlags& flags, const std::string& input,
                                const ReconstructionRun& run, const ShapeErrors* errors);

// The one JSON line `nrsfm evaluate` prints: MetricList, e3d_frame, F, P
// and, when not empty, unscored_frames / unscored_points.
// With num_bases > 0 and rank_floor ≥ 0 also "K" and "rank_floor"
// (ComputeRankFloorE3D of the object-frame truth).
std::string EvaluationJson(const ShapeErrors& errors, int num_bases = 0,
                           double rank_floor = -1.0);

// --output of synth: a path ending in .mat.
Status CheckSynthOutput(const std::string& output);

// `nrsfm synth` without its output: --dataset, --frames, --points, --K,
// --cameras, --noise, --missing, --seed checked and the generator run.
Status Synthesize(const CommandFlags& flags, SyntheticSequence* sequence);

// `nrsfm synth --dataset reproject` without its output: the truth of
// --input (read as --truth is) under the camera path of --rotation, --axis,
// --profile, with --noise_fraction, --missing, --occlusion and --seed
// (core/synthetic.h GenerateReprojection), and the variables of its .mat
// file, written like the Akhter et al. files: W (NaN where missing), S
// (object frame, rows x_t, y_t, z_t), Rs (2F × 3), cameras, image_size,
// noise_stddev and the source's skeleton `list` when it has one. Errors on
// flags that do not apply (--K, --frames, --points, --noise) and bad values.
Status SynthesizeReprojection(const CommandFlags& flags, ReprojectedSequence* sequence,
                              std::vector<MatVariable>* variables);

// What `nrsfm synth` writes into its .mat file: W (NaN where missing),
// P3_gt (camera 0's truth, block layout), rotations_gt, weights_gt,
// basis_gt and cameras.
std::vector<MatVariable> SyntheticVariables(const SyntheticSequence& sequence);

}  // namespace tools
}  // namespace nrsfm

#endif  // NRSFM_TOOLS_FLAG_OPTIONS_H_
