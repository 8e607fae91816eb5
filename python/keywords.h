// The keyword options of the Python module's functions: the nrsfm tool's
// flags (tools/flag_table.h), chosen by command and role, with the Python
// type of each value and its default and help for the docstrings and
// nrsfm.OPTIONS.
#ifndef NRSFM_PYTHON_KEYWORDS_H_
#define NRSFM_PYTHON_KEYWORDS_H_

#include <pybind11/pybind11.h>

#include <functional>
#include <set>
#include <string>
#include <vector>

#include "tools/command_flags.h"
#include "tools/flag_table.h"

namespace nrsfm {
namespace python {

namespace py = pybind11;

struct Flag {
  const tools::FlagInfo* info;  // name, role, help per command
  std::string type;             // "int", "float", "str", "bool"
  std::function<py::object(const tools::CommandFlags&)> get;
  // TypeError naming the flag on a value of another type.
  std::function<void(tools::CommandFlags*, py::handle)> set;
  const std::string& name() const { return info->name; }
};

// Every flag of the tool (tools::CommandFlagTable(), in its order: the
// flags of NRSFM_COMMAND_FLAGS, then one per extra term).
const std::vector<Flag>& Flags();

// The keyword options of a function: the flags of a command of the tool in
// the roles the function takes (tools/command_flags.h FlagRole).
struct FunctionOptions {
  // the tool's command whose flags apply
  tools::Command command = tools::kReconstruct;
  std::vector<const Flag*> flags;  // the keywords, in --help order
};

// reconstruct(W, K, ..., **options): the options of the start, the prior
// rule and the choice of K (kStart), of the problem and the solver (kOption).
const FunctionOptions& ReconstructOptionsOf();
// refine(W, model, ..., **options): the options of the problem and the solver.
const FunctionOptions& RefineOptionsOf();
// read(path, **options): how reconstruct and view read their input (kInput).
const FunctionOptions& ReadOptionsOf();
// synth(**options): every synth flag.
const FunctionOptions& SynthOptionsOf();
// track(frames, queries, mask, **options): the tracker's options.
const FunctionOptions& TrackOptionsOf();
// evaluate(truth, result, **options): truth_var.
const FunctionOptions& EvaluateOptionsOf();

// Sets `flags` from the keyword arguments, except those in `handled`;
// TypeError on a keyword that is not an option of `function`.
void ApplyKeywords(const FunctionOptions& options, const char* function,
                   const py::dict& kwargs, tools::CommandFlags* flags,
                   const std::set<std::string>& handled = {});

// "name: type = default\n    help" for each keyword, for the docstrings.
std::string KeywordDoc(const FunctionOptions& options);

// {name: {"type", "default", "help"}} of a function's keywords.
py::dict KeywordTable(const FunctionOptions& options);

}  // namespace python
}  // namespace nrsfm

#endif  // NRSFM_PYTHON_KEYWORDS_H_
