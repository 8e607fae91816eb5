// The flags of the nrsfm tool, each declared once: NRSFM_COMMAND_FLAGS lists
// type, name, default and help of every flag, and from that one list come
// the members of CommandFlags (what the commands read) and the gflags flags
// that parse into them (RegisterCommandFlags). A flag that sets a library
// option takes that option's default. The extra terms' weights are not in
// the list: one flag per row of the table in problems/extra_terms.h, named
// by its `flag` column, parsed into CommandFlags::term_weights.
#ifndef NRSFM_TOOLS_COMMAND_FLAGS_H_
#define NRSFM_TOOLS_COMMAND_FLAGS_H_

#include <cstdint>
#include <string>
#include <vector>

#include "core/keypoint_io.h"
#include "core/read_measurements.h"
#include "core/synthetic.h"
#include "problems/extra_terms.h"
#include "problems/problem_options.h"
#include "solvers/initialize.h"
#include "solvers/reconstruct.h"
#include "solvers/select_num_bases.h"
#include "solvers/solver_options.h"

// X(type, name, default, help)
#define NRSFM_COMMAND_FLAGS(X)                                                   \
  X(std::string, input, "",                                                      \
    "reconstruct, view: input file (.mat v4/v5/v7.3, text/CSV W, an "            \
    "observation list .obs/.list 'frame camera point u v', COCO keypoint "       \
    "results .json, or a folder of OpenPose .json frames); synth --dataset "    \
    "reproject: the source truth (.mat with S+Rs, P3_gt or X).")                 \
  X(std::string, var, ::nrsfm::InputOptions().variable,                          \
    "reconstruct, view: variable of a .mat input (default: W, then P3_gt, "      \
    "then X).")                                                                  \
  X(std::string, mask_var, ::nrsfm::InputOptions().mask_variable,                \
    "reconstruct, view: optional visibility-mask variable of a .mat input "      \
    "(nonzero = visible).")                                                      \
  X(std::string, format,                                                         \
    ::nrsfm::InputFormatName(::nrsfm::InputOptions().format),                    \
    "reconstruct, view: input format auto|mat|text|list|coco|openpose (auto: "   \
    "by the extension, .json = coco; a folder = openpose).")                     \
  X(std::string, frame_key, ::nrsfm::KeypointOptions().frame_key,                \
    "reconstruct, view: COCO keypoint input: the field of each entry that "      \
    "orders the frames (integers: every number from the smallest to the "       \
    "largest is a frame, one without an entry has no person).")                  \
  X(std::string, part,                                                           \
    ::nrsfm::KeypointPartName(::nrsfm::KeypointOptions().part),                  \
    "reconstruct, view: OpenPose input: the keypoints of people[0] that are "    \
    "the points, pose|face|hand_left|hand_right.")                               \
  X(double, min_confidence, ::nrsfm::KeypointOptions().min_confidence,           \
    "reconstruct, view: keypoint input: a keypoint whose detector score is "     \
    "below this is missing (a score of 0 always is).")                           \
  X(int, cameras, ::nrsfm::InputOptions().num_cameras,                           \
    "reconstruct: number of synchronised cameras M of a W input with 2FM rows; " \
    "0 = what the file records (a .mat file's 'cameras' variable, an "          \
    "observation list's camera indices), else 1; a count that disagrees with "  \
    "the file is an error. synth: cameras of the shoe (1 or 2; 0 = 1).")         \
  X(std::string, K, "",                                                          \
    "reconstruct: number of basis shapes, an integer >= 1 or 'auto'; evaluate: " \
    "the result's K, for the rank-K floor printed beside an object-frame e3D "  \
    "(default: the result directory's result.json); synth: basis shapes of the " \
    "random generator (default: the generator's).")                             \
  X(int, K_max, ::nrsfm::SelectNumBasesOptions().max_num_bases,                  \
    "reconstruct --K auto: largest K tried.")                                    \
  X(double, K_threshold, ::nrsfm::SelectNumBasesOptions().threshold,             \
    "reconstruct --K auto: keep the smallest K whose reprojection RMS is "       \
    "within this factor of the noise level estimated from the data.")            \
  X(std::string, output, "",                                                     \
    "reconstruct: output directory; synth: output .mat file; view: output "      \
    ".html file.")                                                               \
  X(bool, overwrite, false,                                                      \
    "reconstruct: replace an earlier result directory; view: replace the page.") \
  X(bool, ply, false, "reconstruct: also write one PLY file per frame.")         \
  X(std::string, init, ::nrsfm::StartMethodName(::nrsfm::StartOptions().method), \
    "reconstruct: start auto|factorization|rigid|triple (auto: the triple "     \
    "start for a video given the temporal prior; otherwise the factorization "  \
    "and rigid starts both refined, the lower cost kept; docs/priors.md).")     \
  X(std::string, priors,                                                         \
    ::nrsfm::PriorModeName(::nrsfm::ReconstructOptions().priors),                \
    "reconstruct: auto|manual. auto chooses the temporal terms from the data "   \
    "(docs/priors.md); giving any term weight (--temporal_shape, ...) means "    \
    "manual: exactly the weights given.")                                        \
  X(std::string, robust,                                                         \
    ::nrsfm::RobustLossName(::nrsfm::ProblemOptions().robust_loss),              \
    "reconstruct: robust loss none|huber|cauchy on the reprojection terms.")     \
  X(double, robust_scale, ::nrsfm::ProblemOptions().robust_scale,                \
    "reconstruct: robust loss scale, in input units.")                           \
  X(std::string, hold, "",                                                       \
    "reconstruct: blocks held at their start values during the refinement, a "  \
    "comma list of rotations,translations,weights,basis,scales,rig (e.g. "      \
    "your own cameras with --init and refine, or refine in Python).")           \
  X(bool, confidence_weights, false,                                             \
    "reconstruct: keypoint input: weight each observation's residual by its "    \
    "detector score (the scores scaled to average 1 over the visible points).")  \
  X(int, max_iterations, ::nrsfm::SolverOptions().max_iterations,                \
    "reconstruct: Levenberg-Marquardt iterations.")                              \
  X(int, threads, ::nrsfm::SolverOptions().num_threads,                          \
    "reconstruct: solver threads (default: every core; the default solver "    \
    "gives the same bits for any count).")                                     \
  X(std::string, linear_solver,                                                  \
    ::nrsfm::LinearSolverName(::nrsfm::SolverOptions().linear_solver),           \
    "reconstruct: auto|structured|dense_schur|sparse_schur|iterative_schur|"     \
    "sparse_normal_cholesky|cgnr|dense_qr.")                                     \
  X(std::uint64_t, seed, ::nrsfm::StartOptions().seed,                           \
    "reconstruct: seed of the rigid and triple starts; synth: seed.")            \
  X(std::string, truth, "",                                                      \
    "reconstruct, evaluate, view: ground truth (.mat with S+Rs, P3_gt or X, "    \
    "or a result directory).")                                                   \
  X(std::string, truth_var, "",                                                  \
    "reconstruct, evaluate, view: variable of the truth .mat (default: S+Rs, "   \
    "then P3_gt, then X); synth --dataset reproject: variable of the source "  \
    "--input.")                                                                  \
  X(std::string, result, "",                                                     \
    "evaluate, view: result directory of a reconstruction.")                     \
  X(std::string, dataset, "random",                                              \
    "synth: random|superquadric|shoe|reproject (reproject: the 3-D truth of "     \
    "--input re-projected under the camera path of --rotation, --axis, "         \
    "--profile).")                                                               \
  X(int, frames, -1, "synth: frames F (default: the generator's).")              \
  X(int, points, -1, "synth: points P (default: the generator's).")              \
  X(double, noise, 0.0, "synth: Gaussian noise std on W, input units.")          \
  X(double, missing, 0.0,                                                        \
    "synth: fraction of entries removed at random (random, superquadric, "       \
    "reproject).")                                                               \
  X(double, rotation, ::nrsfm::ReprojectOptions().total_rotation_deg,            \
    "synth --dataset reproject: total camera rotation over the sequence, "       \
    "degrees.")                                                                  \
  X(std::string, axis, "0,1,0",                                                  \
    "synth --dataset reproject: rotation axis x,y,z in the first camera's "      \
    "frame (0,1,0: orbit about the image's vertical).")                          \
  X(std::string, profile,                                                        \
    ::nrsfm::SpeedProfileName(::nrsfm::ReprojectOptions().profile),              \
    "synth --dataset reproject: speed profile constant|ramp|stopgo.")            \
  X(double, noise_fraction, ::nrsfm::ReprojectOptions().noise_fraction,          \
    "synth --dataset reproject: Gaussian noise std as a fraction of the image "  \
    "size (the largest side of a frame's bounding box of the tracks).")          \
  X(double, occlusion, ::nrsfm::ReprojectOptions().occlusion_radius,             \
    "synth --dataset reproject: self-occlusion radius as a fraction of the "     \
    "image size (a point is hidden by a nearer one within it); 0 = none.")       \
  X(bool, quiet, false, "reconstruct: no progress lines on stderr.")

namespace nrsfm {
namespace tools {

// The parsed command line; --help describes each member.
struct CommandFlags {
#define NRSFM_COMMAND_FLAG_MEMBER(type, name, value, help) type name = value;
  NRSFM_COMMAND_FLAGS(NRSFM_COMMAND_FLAG_MEMBER)
#undef NRSFM_COMMAND_FLAG_MEMBER
  // λ of every extra term, aligned with ExtraTerms() (0 = off).
  std::vector<double> term_weights = std::vector<double>(ExtraTerms().size(), 0.0);
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
