// The flags of the nrsfm tool, each declared once: NRSFM_COMMAND_FLAGS lists
// type, name, default, role, the option it sets and its help per command of
// every flag. From that one list come the members of CommandFlags (what the
// commands read), the gflags flags that parse into them
// (RegisterCommandFlags), the options they set (ApplyFlags), result.json's
// "options" and the Python module's and MATLAB function's keywords
// (tools/flag_table.h). A flag that sets a library option takes that
// option's default. The extra terms' weights are not in the list: one flag
// per row of the table in problems/extra_terms.h, named by its `name`,
// parsed into CommandFlags::term_weights (tools/flag_table.h adds them).
#ifndef NRSFM_TOOLS_COMMAND_FLAGS_H_
#define NRSFM_TOOLS_COMMAND_FLAGS_H_

#include <cstdint>
#include <string>
#include <vector>

#include "core/io/keypoint_io.h"
#include "core/io/read_measurements.h"
#include "core/model/status.h"
#include "core/synthetic/synthetic.h"
#include "problems/delaunay_edges.h"
#include "problems/extra_terms.h"
#include "problems/problem_options.h"
#include "solvers/pipeline/prior_rule.h"
#include "solvers/pipeline/reconstruct.h"
#include "solvers/pipeline/select_num_bases.h"
#include "solvers/refine/solver_options.h"
#include "solvers/start/alternation.h"
#include "solvers/start/low_rank_completion.h"
#include "solvers/start/start.h"
#include "tools/track_flags.h"
#include "tools/uncertainty_flags.h"

namespace nrsfm {
namespace tools {

// The commands of the tool, as bits: a flag's help names the commands it
// serves.
enum Command : unsigned {
  kReconstruct = 1u,
  kEvaluate = 2u,
  kSynth = 4u,
  kView = 8u,
  kTrack = 16u
};

// What a flag is for, which decides where it appears:
//   kInput     how --input is read (InputOptions): reconstruct and view, the
//              Python read() keywords, result.json's options;
//   kWeights   the keypoint scores as observation weights: result.json's
//              options (a caller of the Python or MATLAB function gives the
//              weights as an array instead);
//   kNumBases  --K (an argument of the Python and MATLAB functions);
//   kStart     an option of the start, of the prior rule or of the choice
//              of K (not of a refinement of a given model): result.json,
//              the keywords of reconstruct() but not of refine();
//   kOption    an option of the problem or the solver: result.json, the
//              keywords of reconstruct() and refine();
//   kSynthesis the synthetic data (synth only);
//   kTracking  an option of the tracker (track only): its result.json;
//   kTool      the tool's own files and printing: none of the above.
enum class FlagRole {
  kInput,
  kWeights,
  kNumBases,
  kStart,
  kOption,
  kSynthesis,
  kTracking,
  kTool
};

// One part of a flag's help: the commands it is for and what it says there.
struct CommandHelp {
  unsigned commands = 0;  // Command bits
  const char* text = "";
};

// --K of reconstruct: an integer >= 1 or "auto"; given = false when empty.
struct NumBasesFlag {
  bool given = false;
  bool automatic = false;
  int value = 0;
};

// Parses --K ("" = not given): an integer >= 1 or "auto"; the error quotes
// the value (the caller names the flag: "must be an integer >= 1 or 'auto',
// got '0'").
Status ParseNumBasesFlag(const std::string& value, NumBasesFlag* num_bases);

// Sets ProblemOptions::constant_* from --hold's comma list of block kinds
// (rotations, translations, weights, basis, scales, rig); an unknown name is
// an error naming it.
Status ParseHeldBlocks(const std::string& list, ProblemOptions* options);

// --intrinsics: "" leaves them to the file's Kcam (empty), else
// ParseIntrinsics (core/io/read_measurements.h).
Status ParseIntrinsicsFlag(const std::string& text,
                           Eigen::Matrix4Xd* intrinsics);

// What the flags set: the options of reading the input, of the
// reconstruction and of the choice of K, and --K itself.
struct FlagTargets {
  InputOptions input;
  ReconstructOptions reconstruct;
  SelectNumBasesOptions select;
  NumBasesFlag num_bases;
  track::TrackOptions track;
  UncertaintyRequest uncertainty;

  // The Check() of each options struct on its own (keypoints, input, start,
  // problem, solver, prior rule, K selection, tracker): the rules of single
  // values.
  Status CheckParts() const;
  // Check() of the input, the reconstruction (with the rules that join
  // values), the K selection and the tracker options.
  Status Check() const;
};

// The `bind` column: how a flag's value sets its field of FlagTargets.
// NRSFM_SETS(target, field) assigns it; NRSFM_PARSES(target, field, parse)
// calls parse(value, &field) (a name parsed into an enum, …);
// NRSFM_PARSES_INTO(target, parse) parses into the target itself;
// NRSFM_SETS_NOTHING: a flag the commands read themselves.
#define NRSFM_SETS(target, field)                          \
  ([](const auto& value, ::nrsfm::tools::FlagTargets* t) { \
    t->target.field = value;                               \
    return ::nrsfm::Status::OK();                          \
  })
#define NRSFM_PARSES(target, field, parse)                 \
  ([](const auto& value, ::nrsfm::tools::FlagTargets* t) { \
    return parse(value, &t->target.field);                 \
  })
#define NRSFM_PARSES_INTO(target, parse)                   \
  ([](const auto& value, ::nrsfm::tools::FlagTargets* t) { \
    return parse(value, &t->target);                       \
  })
#define NRSFM_SETS_NOTHING (::nrsfm::tools::SetsNothing())
#define NRSFM_HELP(...) (std::vector<::nrsfm::tools::CommandHelp>{__VA_ARGS__})

// The bind of a flag that sets no option.
struct SetsNothing {};

}  // namespace tools
}  // namespace nrsfm

// X(type, name, default, role, bind, help): the member's type, the flag's
// name, its default (a library option's own default where it sets one), its
// FlagRole, how it sets its option (NRSFM_SETS / NRSFM_PARSES, or
// NRSFM_SETS_NOTHING for the flags a command reads itself) and its help per
// command (NRSFM_HELP({commands, text}, ...)). The help says what the flag
// does; which commands it serves comes from the commands of its help, not
// from its words.
#define NRSFM_COMMAND_FLAGS(X)                                                 \
  X(std::string, input, "", kTool, NRSFM_SETS_NOTHING,                         \
    NRSFM_HELP(                                                                \
        {kReconstruct | kView,                                                 \
         "input file (.mat v4/v5/v7.3, text/CSV W, an observation list "       \
         ".obs/.list 'frame camera point u v', COCO keypoint results "         \
         ".json, or a folder of OpenPose .json frames)."},                     \
        {kSynth,                                                               \
         "(--dataset reproject) the source truth (.mat with "                  \
         "S+Rs, P3_gt or X)."}))                                               \
  X(std::string, var, ::nrsfm::InputOptions().variable, kInput,                \
    NRSFM_SETS(input, variable),                                               \
    NRSFM_HELP({kReconstruct | kView,                                          \
                "variable of a .mat input (default: W, "                       \
                "then P3_gt, then X)."}))                                      \
  X(std::string, mask_var, ::nrsfm::InputOptions().mask_variable, kInput,      \
    NRSFM_SETS(input, mask_variable),                                          \
    NRSFM_HELP({kReconstruct | kView,                                          \
                "optional visibility-mask variable of a "                      \
                ".mat input (nonzero = visible)."}))                           \
  X(std::string, format,                                                       \
    ::nrsfm::InputFormatName(::nrsfm::InputOptions().format), kInput,          \
    NRSFM_PARSES(input, format, ::nrsfm::ParseInputFormat),                    \
    NRSFM_HELP({kReconstruct | kView,                                          \
                "input format (auto: by the extension, .json = coco; a "       \
                "folder = openpose)."}))                                       \
  X(std::string, frame_key, ::nrsfm::KeypointOptions().frame_key, kInput,      \
    NRSFM_SETS(input, keypoints.frame_key),                                    \
    NRSFM_HELP(                                                                \
        {kReconstruct | kView,                                                 \
         "COCO keypoint input: the field of each entry that orders the "       \
         "frames (integers: every number from the smallest to the "            \
         "largest is a frame, one without an entry has no person)."}))         \
  X(std::string, part,                                                         \
    ::nrsfm::KeypointPartName(::nrsfm::KeypointOptions().part), kInput,        \
    NRSFM_PARSES(input, keypoints.part, ::nrsfm::ParseKeypointPart),           \
    NRSFM_HELP({kReconstruct | kView,                                          \
                "OpenPose input: the keypoints of people[0] that are the "     \
                "points."}))                                                   \
  X(double, min_confidence, ::nrsfm::KeypointOptions().min_confidence, kInput, \
    NRSFM_SETS(input, keypoints.min_confidence),                               \
    NRSFM_HELP(                                                                \
        {kReconstruct | kView,                                                 \
         "keypoint input: a keypoint whose detector score is below this "      \
         "is missing (a score of 0 always is)."}))                             \
  X(std::string, intrinsics, "", kInput,                                       \
    NRSFM_PARSES(input, intrinsics, ParseIntrinsicsFlag),                      \
    NRSFM_HELP({kReconstruct | kView,                                          \
                "pinhole intrinsics fx,fy,cx,cy in pixels (several cameras: "  \
                "one group each, joined by ';'); replace the .mat's Kcam; "    \
                "'' = Kcam when the file has it."}))                           \
  X(int, cameras, ::nrsfm::InputOptions().num_cameras, kInput,                 \
    NRSFM_SETS(input, num_cameras),                                            \
    NRSFM_HELP(                                                                \
        {kReconstruct,                                                         \
         "number of synchronised cameras M of a W input with 2FM rows; "       \
         "0 = what the file records (a .mat file's 'cameras' variable, "       \
         "an observation list's camera indices), else 1; a count that "        \
         "disagrees with the file is an error."},                              \
        {kSynth, "cameras of the shoe (1 or 2; 0 = 1)."}))                     \
  X(std::string, K, "", kNumBases,                                             \
    NRSFM_PARSES_INTO(num_bases, ParseNumBasesFlag),                           \
    NRSFM_HELP({kReconstruct,                                                  \
                "number of basis shapes, an integer >= 1 or "                  \
                "'auto'."},                                                    \
               {kEvaluate,                                                     \
                "the result's K, for the rank-K floor printed "                \
                "beside an object-frame e3D (default: the result "             \
                "directory's result.json)."},                                  \
               {kSynth,                                                        \
                "basis shapes of the random generator (default: the "          \
                "generator's)."}))                                             \
  X(int, K_max, ::nrsfm::SelectNumBasesOptions().max_num_bases, kStart,        \
    NRSFM_SETS(select, max_num_bases),                                         \
    NRSFM_HELP({kReconstruct, "(--K auto) largest K tried."}))                 \
  X(double, K_threshold, ::nrsfm::SelectNumBasesOptions().threshold, kStart,   \
    NRSFM_SETS(select, threshold),                                             \
    NRSFM_HELP({kReconstruct,                                                  \
                "(--K auto) keep the smallest K whose "                        \
                "reprojection RMS is within this factor of the "               \
                "noise level estimated from the data."}))                      \
  X(std::string, output, "", kTool, NRSFM_SETS_NOTHING,                        \
    NRSFM_HELP(                                                                \
        {kReconstruct, "output directory."}, {kSynth, "output .mat file."},    \
        {kView, "output .html file."},                                         \
        {kTrack, "output folder (tracks.csv, tracks.mat, result.json)."}))     \
  X(bool, overwrite, false, kTool, NRSFM_SETS_NOTHING,                         \
    NRSFM_HELP({kReconstruct, "replace an earlier result directory."},         \
               {kView, "replace the page."},                                   \
               {kTrack, "replace an earlier track folder."}))                  \
  X(bool, ply, false, kTool, NRSFM_SETS_NOTHING,                               \
    NRSFM_HELP({kReconstruct, "also write one PLY file per frame."}))          \
  X(std::string, init,                                                         \
    ::nrsfm::StartMethodName(::nrsfm::StartOptions().method), kStart,          \
    NRSFM_PARSES(reconstruct, start.method, ::nrsfm::ParseStartMethod),        \
    NRSFM_HELP({kReconstruct,                                                  \
                "the start (auto: the triple start "                           \
                "for a video given the temporal prior; otherwise the "         \
                "factorization and rigid starts both refined, the lower cost " \
                "kept; docs/priors.md)."}))                                    \
  X(std::string, camera,                                                       \
    ::nrsfm::CameraModelName(::nrsfm::ReconstructOptions().camera), kStart,    \
    NRSFM_PARSES(reconstruct, camera, ::nrsfm::ParseCameraModel),              \
    NRSFM_HELP({kReconstruct,                                                  \
                "the camera. perspective: a calibrated "                       \
                "pinhole camera (intrinsics from the .mat's Kcam or "          \
                "--intrinsics), refined from the weak-perspective answer; "    \
                "outputs in the camera frame up to one global scale "          \
                "(--depth; docs/camera.md)."}))                                \
  X(double, depth, ::nrsfm::ReconstructOptions().depth, kStart,                \
    NRSFM_SETS(reconstruct, depth),                                            \
    NRSFM_HELP({kReconstruct,                                                  \
                "--camera perspective: the mean depth of the first frame's "   \
                "points, in the units you want the output in; 0 = fx "         \
                "(a unit is then about a pixel at that depth)."}))             \
  X(std::string, priors,                                                       \
    ::nrsfm::PriorModeName(::nrsfm::ReconstructOptions().priors), kStart,      \
    NRSFM_PARSES(reconstruct, priors, ::nrsfm::ParsePriorMode),                \
    NRSFM_HELP({kReconstruct,                                                  \
                "auto chooses the temporal terms from the data "               \
                "(docs/priors.md); giving any term weight (--temporal_shape, " \
                "...) means manual: exactly the weights given."}))             \
  X(std::string, robust,                                                       \
    ::nrsfm::RobustLossName(::nrsfm::ProblemOptions().robust_loss), kOption,   \
    NRSFM_PARSES(reconstruct, problem.robust_loss, ::nrsfm::ParseRobustLoss),  \
    NRSFM_HELP({kReconstruct, "robust loss on the reprojection terms."}))      \
  X(double, robust_scale, ::nrsfm::ProblemOptions().robust_scale, kOption,     \
    NRSFM_SETS(reconstruct, problem.robust_scale),                             \
    NRSFM_HELP({kReconstruct, "robust loss scale, in input units."}))          \
  X(std::string, hold, "", kOption,                                            \
    NRSFM_PARSES(reconstruct, problem, ParseHeldBlocks),                       \
    NRSFM_HELP({kReconstruct,                                                  \
                "blocks held at their start values during the refinement, a "  \
                "comma list of these kinds "                                   \
                "(e.g. your own cameras with --init and refine, or refine in " \
                "Python)."}))                                                  \
  X(bool, confidence_weights, false, kWeights, NRSFM_SETS_NOTHING,             \
    NRSFM_HELP({kReconstruct,                                                  \
                "keypoint input: weight each observation's residual by its "   \
                "detector score (the scores scaled to average 1 over the "     \
                "visible points)."}))                                          \
  X(int, max_iterations, ::nrsfm::SolverOptions().max_iterations, kOption,     \
    NRSFM_SETS(reconstruct, solver.max_iterations),                            \
    NRSFM_HELP({kReconstruct, "Levenberg-Marquardt iterations."}))             \
  X(double, function_tolerance, ::nrsfm::SolverOptions().function_tolerance,   \
    kOption, NRSFM_SETS(reconstruct, solver.function_tolerance),               \
    NRSFM_HELP({kReconstruct,                                                  \
                "stop when an accepted step lowers the cost by "               \
                "less than this fraction of itself."}))                        \
  X(double, max_seconds, ::nrsfm::SolverOptions().max_seconds, kOption,        \
    NRSFM_SETS(reconstruct, solver.max_seconds),                               \
    NRSFM_HELP({kReconstruct,                                                  \
                "wall-time limit of each refinement, seconds; "                \
                "0 = none."}))                                                 \
  X(int, threads, ::nrsfm::SolverOptions().num_threads, kOption,               \
    NRSFM_SETS(reconstruct, solver.num_threads),                               \
    NRSFM_HELP({kReconstruct,                                                  \
                "solver threads (default: every core; the "                    \
                "default solver gives the same bits for any "                  \
                "count)."}))                                                   \
  X(std::string, minimizer,                                                    \
    ::nrsfm::MinimizerName(::nrsfm::SolverOptions().minimizer), kOption,       \
    NRSFM_PARSES(reconstruct, solver.minimizer, ::nrsfm::ParseMinimizer),      \
    NRSFM_HELP({kReconstruct,                                                  \
                "the minimiser: structured, our Levenberg-Marquardt on the "   \
                "problem (auto where it fits) or ceres::Solve with "           \
                "--linear_solver (docs/problem.md)."}))                        \
  X(std::string, linear_solver,                                                \
    ::nrsfm::LinearSolverName(::nrsfm::SolverOptions().linear_solver),         \
    kOption,                                                                   \
    NRSFM_PARSES(reconstruct, solver.linear_solver,                            \
                 ::nrsfm::ParseLinearSolver),                                  \
    NRSFM_HELP({kReconstruct,                                                  \
                "Ceres' linear solver with --minimizer ceres "                 \
                "(structured: --minimizer structured)."}))                     \
  X(double, gradient_tolerance, ::nrsfm::SolverOptions().gradient_tolerance,   \
    kOption, NRSFM_SETS(reconstruct, solver.gradient_tolerance),               \
    NRSFM_HELP(                                                                \
        {kReconstruct,                                                         \
         "stop when the largest projected gradient entry is below this."}))    \
  X(double, parameter_tolerance, ::nrsfm::SolverOptions().parameter_tolerance, \
    kOption, NRSFM_SETS(reconstruct, solver.parameter_tolerance),              \
    NRSFM_HELP(                                                                \
        {kReconstruct, "stop when a step is below this times (|x| + this)."})) \
  X(double, initial_radius,                                                    \
    ::nrsfm::SolverOptions().initial_trust_region_radius, kOption,             \
    NRSFM_SETS(reconstruct, solver.initial_trust_region_radius),               \
    NRSFM_HELP(                                                                \
        {kReconstruct,                                                         \
         "Levenberg-Marquardt's first trust-region radius (1/damping)."}))     \
  X(double, cg_tolerance, ::nrsfm::SolverOptions().cg_relative_tolerance,      \
    kOption, NRSFM_SETS(reconstruct, solver.cg_relative_tolerance),            \
    NRSFM_HELP({kReconstruct,                                                  \
                "structured solver: conjugate gradients stop at this "         \
                "relative residual, in (0, 1)."}))                             \
  X(int, max_cg_iterations, ::nrsfm::SolverOptions().max_cg_iterations,        \
    kOption, NRSFM_SETS(reconstruct, solver.max_cg_iterations),                \
    NRSFM_HELP({kReconstruct,                                                  \
                "structured solver: conjugate-gradient iterations per step, "  \
                "at most."}))                                                  \
  X(int, verbosity, ::nrsfm::SolverOptions().verbosity, kOption,               \
    NRSFM_SETS(reconstruct, solver.verbosity),                                 \
    NRSFM_HELP({kReconstruct,                                                  \
                "1 = one log line per iteration on stderr (with --v=1)."}))    \
  X(int, smoothness_hidden_neighbours,                                         \
    ::nrsfm::DelaunayEdgesOptions().num_hidden_neighbours, kOption,            \
    NRSFM_SETS(reconstruct, problem.smoothness_edges.num_hidden_neighbours),   \
    NRSFM_HELP({kReconstruct,                                                  \
                "--smoothness: the triangulated points each point outside "    \
                "the triangulation is joined to."}))                           \
  X(int, completion_iterations,                                                \
    ::nrsfm::LowRankCompletionOptions().max_iterations, kStart,                \
    NRSFM_SETS(reconstruct, start.completion.max_iterations),                  \
    NRSFM_HELP({kReconstruct,                                                  \
                "missing entries: rounds of the start's rank-3K completion, "  \
                "at most."}))                                                  \
  X(double, completion_ridge_floor,                                            \
    ::nrsfm::LowRankCompletionOptions().ridge_floor, kStart,                   \
    NRSFM_SETS(reconstruct, start.completion.ridge_floor),                     \
    NRSFM_HELP({kReconstruct,                                                  \
                "missing entries: the completion's ridge floor, relative to "  \
                "the data RMS."}))                                             \
  X(int, alternation_rounds, ::nrsfm::AlternationOptions().rounds, kStart,     \
    NRSFM_SETS(reconstruct, start.alternation.rounds),                         \
    NRSFM_HELP({kReconstruct,                                                  \
                "rounds of the rigid and triple starts' basis/weights "        \
                "alternation."}))                                              \
  X(double, alternation_initial_deformation,                                   \
    ::nrsfm::AlternationOptions().initial_deformation, kStart,                 \
    NRSFM_SETS(reconstruct, start.alternation.initial_deformation),            \
    NRSFM_HELP({kReconstruct,                                                  \
                "std of the random initial weights of bases 2..K of the "      \
                "rigid and triple starts."}))                                  \
  X(double, rule_min_track_order, ::nrsfm::PriorRuleOptions().min_track_order, \
    kStart, NRSFM_SETS(reconstruct, prior_rule.min_track_order),               \
    NRSFM_HELP({kReconstruct,                                                  \
                "(--priors auto) the track order from which the tracks are a " \
                "video (docs/priors.md)."}))                                   \
  X(double, rule_min_basis_fraction,                                           \
    ::nrsfm::PriorRuleOptions().min_basis_fraction, kStart,                    \
    NRSFM_SETS(reconstruct, prior_rule.min_basis_fraction),                    \
    NRSFM_HELP({kReconstruct,                                                  \
                "(--priors auto) 3K/P from which the basis absorbs rotation "  \
                "(docs/priors.md)."}))                                         \
  X(double, rule_temporal_shape_weight,                                        \
    ::nrsfm::PriorRuleOptions().temporal_shape_weight, kStart,                 \
    NRSFM_SETS(reconstruct, prior_rule.temporal_shape_weight),                 \
    NRSFM_HELP(                                                                \
        {kReconstruct,                                                         \
         "(--priors auto) the temporal shape prior's weight for a video."}))   \
  X(double, rule_min_temporal_shape_weight,                                    \
    ::nrsfm::PriorRuleOptions().min_temporal_shape_weight, kStart,             \
    NRSFM_SETS(reconstruct, prior_rule.min_temporal_shape_weight),             \
    NRSFM_HELP({kReconstruct,                                                  \
                "(--priors auto) the temporal shape prior's weight when the "  \
                "start's frames deform independently (docs/priors.md)."}))     \
  X(double, rule_deformation_weight,                                           \
    ::nrsfm::PriorRuleOptions().deformation_weight, kStart,                    \
    NRSFM_SETS(reconstruct, prior_rule.deformation_weight),                    \
    NRSFM_HELP({kReconstruct,                                                  \
                "(--priors auto) the deformation prior's weight when the "     \
                "tracks are not a video."}))                                   \
  X(double, rule_rigidity_weight, ::nrsfm::PriorRuleOptions().rigidity_weight, \
    kStart, NRSFM_SETS(reconstruct, prior_rule.rigidity_weight),               \
    NRSFM_HELP({kReconstruct,                                                  \
                "(--priors auto) the rigidity's weight with several cameras, " \
                "(spread / rad)^2 (docs/priors.md)."}))                        \
  X(double, rule_max_path_acceleration_deg,                                    \
    ::nrsfm::PriorRuleOptions().max_path_acceleration_deg, kStart,             \
    NRSFM_SETS(reconstruct, prior_rule.max_path_acceleration_deg),             \
    NRSFM_HELP(                                                                \
        {kReconstruct,                                                         \
         "(--priors auto) the start's camera-path acceleration, deg/frame^2, " \
         "below which the rotation prior is tried; 0 = never."}))              \
  X(double, rule_max_prior_fit_ratio,                                          \
    ::nrsfm::PriorRuleOptions().max_prior_fit_ratio, kStart,                   \
    NRSFM_SETS(reconstruct, prior_rule.max_prior_fit_ratio),                   \
    NRSFM_HELP({kReconstruct,                                                  \
                "(--priors auto) the path prior is kept when the tracks are "  \
                "fitted within this factor (RMS) of the fit without it."}))    \
  X(double, rule_rotation_acceleration_weight,                                 \
    ::nrsfm::PriorRuleOptions().rotation_acceleration_weight, kStart,          \
    NRSFM_SETS(reconstruct, prior_rule.rotation_acceleration_weight),          \
    NRSFM_HELP(                                                                \
        {kReconstruct, "(--priors auto) the rotation prior's weight."}))       \
  X(double, rule_camera_rank_fraction,                                         \
    ::nrsfm::PriorRuleOptions().camera_rank_fraction, kStart,                  \
    NRSFM_SETS(reconstruct, prior_rule.camera_rank_fraction),                  \
    NRSFM_HELP({kReconstruct,                                                  \
                "(--priors auto) the camera stage's 3K_cam at most this "      \
                "times min(P, 2FM)."}))                                        \
  X(double, rule_camera_fit_threshold,                                         \
    ::nrsfm::PriorRuleOptions().camera_fit_threshold, kStart,                  \
    NRSFM_SETS(reconstruct, prior_rule.camera_fit_threshold),                  \
    NRSFM_HELP({kReconstruct,                                                  \
                "(--priors auto) K_cam explains the tracks within this "       \
                "factor of the noise."}))                                      \
  X(double, rule_camera_function_tolerance,                                    \
    ::nrsfm::PriorRuleOptions().camera_function_tolerance, kStart,             \
    NRSFM_SETS(reconstruct, prior_rule.camera_function_tolerance),             \
    NRSFM_HELP({kReconstruct,                                                  \
                "(--priors auto) the camera stage's function tolerance."}))    \
  X(std::uint64_t, seed, ::nrsfm::StartOptions().seed, kStart,                 \
    NRSFM_SETS(reconstruct, start.seed),                                       \
    NRSFM_HELP({kReconstruct, "seed of the rigid and triple starts."},         \
               {kSynth, "seed."}))                                             \
  X(int, smoothness_reference_frame,                                           \
    ::nrsfm::DelaunayEdgesOptions().reference_frame, kOption,                  \
    NRSFM_SETS(reconstruct, problem.smoothness_edges.reference_frame),         \
    NRSFM_HELP({kReconstruct,                                                  \
                "--smoothness: the frame whose camera-0 view is "              \
                "triangulated for the neighbour edges; -1 = the "              \
                "frame that sees the most points."}))                          \
  X(std::string, truth, "", kTool, NRSFM_SETS_NOTHING,                         \
    NRSFM_HELP({kReconstruct | kEvaluate | kView,                              \
                "ground truth (.mat with S+Rs, P3_gt or X, or a result "       \
                "directory)."}))                                               \
  X(std::string, truth_var, "", kTool, NRSFM_SETS_NOTHING,                     \
    NRSFM_HELP({kReconstruct | kEvaluate | kView,                              \
                "variable of the truth .mat (default: S+Rs, then P3_gt, then " \
                "X)."},                                                        \
               {kSynth,                                                        \
                "(--dataset reproject) variable of the source "                \
                "--input."}))                                                  \
  X(std::string, result, "", kTool, NRSFM_SETS_NOTHING,                        \
    NRSFM_HELP({kEvaluate | kView, "result directory of a reconstruction."}))  \
  X(std::string, dataset, "random", kSynthesis, NRSFM_SETS_NOTHING,            \
    NRSFM_HELP({kSynth,                                                        \
                "the generator (reproject: the "                               \
                "3-D truth of --input re-projected under the camera "          \
                "path of --rotation, --axis, --profile)."}))                   \
  X(int, frames, -1, kSynthesis, NRSFM_SETS_NOTHING,                           \
    NRSFM_HELP({kSynth, "frames F (default: the generator's)."}))              \
  X(int, points, -1, kSynthesis, NRSFM_SETS_NOTHING,                           \
    NRSFM_HELP({kSynth, "points P (default: the generator's)."}))              \
  X(double, noise, 0.0, kSynthesis, NRSFM_SETS_NOTHING,                        \
    NRSFM_HELP({kSynth, "Gaussian noise std on W, input units."}))             \
  X(double, missing, 0.0, kSynthesis, NRSFM_SETS_NOTHING,                      \
    NRSFM_HELP({kSynth,                                                        \
                "fraction of entries removed at random (random, "              \
                "superquadric, reproject)."}))                                 \
  X(double, rotation, ::nrsfm::ReprojectOptions().total_rotation_deg,          \
    kSynthesis, NRSFM_SETS_NOTHING,                                            \
    NRSFM_HELP({kSynth,                                                        \
                "(--dataset reproject) total camera rotation over the "        \
                "sequence, degrees."}))                                        \
  X(std::string, axis, "0,1,0", kSynthesis, NRSFM_SETS_NOTHING,                \
    NRSFM_HELP({kSynth,                                                        \
                "(--dataset reproject) rotation axis x,y,z in the "            \
                "first camera's frame (0,1,0: orbit about the image's "        \
                "vertical)."}))                                                \
  X(std::string, profile,                                                      \
    ::nrsfm::SpeedProfileName(::nrsfm::ReprojectOptions().profile),            \
    kSynthesis, NRSFM_SETS_NOTHING,                                            \
    NRSFM_HELP({kSynth, "(--dataset reproject) speed profile."}))              \
  X(double, noise_fraction, ::nrsfm::ReprojectOptions().noise_fraction,        \
    kSynthesis, NRSFM_SETS_NOTHING,                                            \
    NRSFM_HELP({kSynth,                                                        \
                "(--dataset reproject) Gaussian noise std as a "               \
                "fraction of the image size (the largest side of a "           \
                "frame's bounding box of the tracks)."}))                      \
  X(double, occlusion, ::nrsfm::ReprojectOptions().occlusion_radius,           \
    kSynthesis, NRSFM_SETS_NOTHING,                                            \
    NRSFM_HELP({kSynth,                                                        \
                "(--dataset reproject) self-occlusion radius as a "            \
                "fraction of the image size (a point is hidden by a "          \
                "nearer one within it); 0 = none."}))                          \
  X(double, distance_ratio, ::nrsfm::ReprojectOptions().distance_ratio,        \
    kSynthesis, NRSFM_SETS_NOTHING,                                            \
    NRSFM_HELP({kSynth,                                                        \
                "(--dataset reproject) 0: orthographic camera; > 0: a "        \
                "pinhole camera this many object sizes away (writes Kcam "     \
                "and the camera-frame truth X, pixels)."}))                    \
  X(bool, quiet, false, kTool, NRSFM_SETS_NOTHING,                             \
    NRSFM_HELP({kReconstruct | kTrack, "no progress lines on stderr."}))       \
  NRSFM_TRACK_FLAGS(X)                                                         \
  NRSFM_UNCERTAINTY_FLAGS(X)

namespace nrsfm {
namespace tools {

// The parsed command line; --help describes each member.
struct CommandFlags {
#define NRSFM_COMMAND_FLAG_MEMBER(type, name, value, role, bind, help) \
  type name = value;
  NRSFM_COMMAND_FLAGS(NRSFM_COMMAND_FLAG_MEMBER)
#undef NRSFM_COMMAND_FLAG_MEMBER
  // λ of every extra term, aligned with ExtraTerms() (0 = off).
  std::vector<double> term_weights =
      std::vector<double>(ExtraTerms().size(), 0.0);
};

// Substring of the file name every flag of the tool is registered under
// (gflags::ShowUsageWithFlagsRestrict shows only these).
inline constexpr char kCommandFlagsFile[] = "nrsfm_command_flags";

// Registers every member of `*flags` as a gflags flag whose storage is that
// member (the extra terms as --<flag> doubles). Call once, before
// gflags::ParseCommandLineFlags, with an object that lives as long as the
// program; CHECKs that it is called once.
void RegisterCommandFlags(CommandFlags* flags);

}  // namespace tools
}  // namespace nrsfm

#endif  // NRSFM_TOOLS_COMMAND_FLAGS_H_
