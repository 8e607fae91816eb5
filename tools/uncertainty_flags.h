// The flags of reconstruct's uncertainty (docs/uncertainty.md), rows of the
// one flag list NRSFM_COMMAND_FLAGS of tools/command_flags.h (same columns,
// same rules; the defaults are UncertaintyOptions', solvers/uncertainty/
// uncertainty.h). Role kStart: result.json's options and the keywords of
// reconstruct(), not of refine().
#ifndef NRSFM_TOOLS_UNCERTAINTY_FLAGS_H_
#define NRSFM_TOOLS_UNCERTAINTY_FLAGS_H_

#include "solvers/uncertainty/uncertainty.h"

namespace nrsfm {
namespace tools {

// What --uncertainty and --noise_std set.
struct UncertaintyRequest {
  bool compute = false;
  UncertaintyOptions options;
};

}  // namespace tools
}  // namespace nrsfm

#define NRSFM_UNCERTAINTY_FLAGS(X)                                            \
  X(bool, uncertainty, false, kStart, NRSFM_SETS(uncertainty, compute),       \
    NRSFM_HELP({kReconstruct,                                                 \
                "also the covariance of every point and rotation "            \
                "(points_covariance.csv, rotations_covariance.csv) from the " \
                "Gauss-Newton information matrix at the solution."}))         \
  X(double, noise_std, ::nrsfm::UncertaintyOptions().noise_std, kStart,       \
    NRSFM_SETS(uncertainty, options.noise_std),                               \
    NRSFM_HELP({kReconstruct,                                                 \
                "--uncertainty: the noise std per image coordinate, input "   \
                "units; 0 = estimated from the fit."}))

#endif  // NRSFM_TOOLS_UNCERTAINTY_FLAGS_H_
