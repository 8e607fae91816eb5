// Helpers of the MEX functions (matlab/nrsfm_reconstruct.cc,
// matlab/nrsfm_track.cc): arrays and option values from MATLAB / Octave in
// the C MEX API both share, each failure a Status naming the argument.
#ifndef NRSFM_MATLAB_MEX_UTIL_H_
#define NRSFM_MATLAB_MEX_UTIL_H_

#include <Eigen/Core>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/model/status.h"
#include "mex.h"
#include "tools/command_flags.h"
#include "tools/flag_table.h"

namespace nrsfm {
namespace mex {

std::string Lower(std::string s);
// "2 x 3 x 4".
std::string SizeText(const mxArray* a);
// A real, full, 2-D numeric or logical array as a double matrix; `name`
// names it in errors.
Status ToMatrix(const mxArray* a, const std::string& name,
                Eigen::MatrixXd* out);
// An option's value as the tool's flag text: a char row, a logical or a
// numeric real scalar.
Status ValueText(const mxArray* a, const std::string& name, std::string* text);
// The tool's flags of `roles` a function takes by name: lower-case name ->
// flag name.
std::vector<std::pair<std::string, std::string>> OptionNames(
    const std::vector<tools::FlagRole>& roles);
// Sets the tool's flag `name` (any case; one of `names`, from OptionNames)
// from `value` (ValueText). An unknown name is an error listing `others`
// (the function's own options, ", "-separated) and the flags.
Status SetOption(const std::vector<std::pair<std::string, std::string>>& names,
                 const std::string& name, const mxArray* value,
                 const std::string& others, tools::CommandFlags* flags);
// A double array of these dimensions, zeros.
mxArray* NewArray(std::vector<mwSize> dims);
// Runs `run` and returns its error text: "" on success, the Status's
// message, or "internal error: …" for an exception. A MEX function raises
// it only after every C++ object of the call is gone (MATLAB's
// mexErrMsgIdAndTxt does not unwind C++ frames).
std::string ErrorOf(const std::function<Status()>& run);

}  // namespace mex
}  // namespace nrsfm

#endif  // NRSFM_MATLAB_MEX_UTIL_H_
