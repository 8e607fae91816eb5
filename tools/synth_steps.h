// The steps of `nrsfm synth` that the tool (tools/commands.h) and the Python
// module's synth() share: the synthetic generators run from the flags and
// the variables of the .mat file they write. Nothing here prints; library
// target nrsfm_tools.
#ifndef NRSFM_TOOLS_SYNTH_STEPS_H_
#define NRSFM_TOOLS_SYNTH_STEPS_H_

#include <string>
#include <vector>

#include "core/io/mat_io.h"
#include "core/model/status.h"
#include "core/synthetic/synthetic.h"
#include "tools/command_flags.h"

namespace nrsfm {
namespace tools {

// --dataset of synth: random, superquadric, shoe or reproject.
Status CheckSynthDataset(const std::string& dataset);

// --output of synth: a path ending in .mat.
Status CheckSynthOutput(const std::string& output);

// `nrsfm synth` without its output: --dataset, --frames, --points, --K,
// --cameras, --noise, --missing, --seed checked and the generator run.
Status Synthesize(const CommandFlags& flags, SyntheticSequence* sequence);

// `nrsfm synth --dataset reproject` without its output: the truth of
// --input (read as --truth is) under the camera path of --rotation, --axis,
// --profile, with --noise_fraction, --missing, --occlusion and --seed
// (core/synthetic/synthetic.h GenerateReprojection), and the variables of its
// .mat file, written like the Akhter et al. files: W (NaN where missing), S
// (object frame, rows x_t, y_t, z_t), Rs (2F × 3), cameras, image_size,
// noise_stddev and the source's skeleton `list` when it has one. Errors on
// flags that do not apply (--K, --frames, --points, --noise) and bad values.
Status SynthesizeReprojection(const CommandFlags& flags,
                              ReprojectedSequence* sequence,
                              std::vector<MatVariable>* variables);

// What `nrsfm synth` writes into its .mat file: W (NaN where missing),
// P3_gt (camera 0's truth, block layout), rotations_gt, weights_gt,
// basis_gt and cameras.
std::vector<MatVariable> SyntheticVariables(const SyntheticSequence& sequence);

}  // namespace tools
}  // namespace nrsfm

#endif  // NRSFM_TOOLS_SYNTH_STEPS_H_
