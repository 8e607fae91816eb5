#include "python/keywords.h"

#include <glog/logging.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "problems/extra_terms.h"
#include "python/convert.h"
#include "tools/command_flags.h"
#include "tools/flag_table.h"

namespace py = pybind11;

namespace nrsfm {
namespace python {

using tools::CommandFlags;

// ---------------------------------------------------------------------------
// Keyword options: the tool's flags.

template <typename T>
struct FlagType;

template <>
struct FlagType<std::string> {
  static constexpr const char* kName = "str";
  static py::object ToPython(const std::string& value) {
    return py::str(value);
  }
  static std::string FromPython(py::handle value, const std::string& name) {
    if (!py::isinstance<py::str>(value)) {
      throw py::type_error(
          name + " must be a str, got " +
          std::string(py::str(py::type::of(value).attr("__name__"))));
    }
    return value.cast<std::string>();
  }
};

template <>
struct FlagType<int> {
  static constexpr const char* kName = "int";
  static py::object ToPython(int value) { return py::int_(value); }
  static int FromPython(py::handle value, const std::string& name) {
    const long long v = IntegerFromPython(value, name);
    if (v < -tools::kMaxFlagInteger || v > tools::kMaxFlagInteger) {
      throw py::value_error(name + " is out of range, got " +
                            std::to_string(v));
    }
    return static_cast<int>(v);
  }
};

template <>
struct FlagType<std::uint64_t> {
  static constexpr const char* kName = "int";
  static py::object ToPython(std::uint64_t value) { return py::int_(value); }
  static std::uint64_t FromPython(py::handle value, const std::string& name) {
    if (py::isinstance<py::bool_>(value) || !PyIndex_Check(value.ptr())) {
      throw py::type_error(
          name + " must be an int, got " +
          std::string(py::str(py::type::of(value).attr("__name__"))));
    }
    py::int_ index =
        py::reinterpret_steal<py::int_>(PyNumber_Index(value.ptr()));
    const unsigned long long v = PyLong_AsUnsignedLongLong(index.ptr());
    if (PyErr_Occurred()) {
      PyErr_Clear();
      throw py::value_error(name + " must be an integer in [0, 2^64)");
    }
    return static_cast<std::uint64_t>(v);
  }
};

template <>
struct FlagType<double> {
  static constexpr const char* kName = "float";
  static py::object ToPython(double value) { return py::float_(value); }
  static double FromPython(py::handle value, const std::string& name) {
    if (py::isinstance<py::bool_>(value) ||
        !(PyFloat_Check(value.ptr()) || PyIndex_Check(value.ptr()) ||
          py::hasattr(value, "__float__"))) {
      throw py::type_error(
          name + " must be a float, got " +
          std::string(py::str(py::type::of(value).attr("__name__"))));
    }
    const double v = PyFloat_AsDouble(value.ptr());
    if (PyErr_Occurred()) throw py::error_already_set();
    return v;
  }
};

template <>
struct FlagType<bool> {
  static constexpr const char* kName = "bool";
  static py::object ToPython(bool value) { return py::bool_(value); }
  static bool FromPython(py::handle value, const std::string& name) {
    if (!py::isinstance<py::bool_>(value)) {
      throw py::type_error(
          name + " must be a bool, got " +
          std::string(py::str(py::type::of(value).attr("__name__"))));
    }
    return value.cast<bool>();
  }
};

// Every flag of the tool (tools::CommandFlagTable(), in its order: the
// flags of NRSFM_COMMAND_FLAGS, then one per extra term).
const std::vector<Flag>& Flags() {
  static const std::vector<Flag> flags = [] {
    const std::vector<tools::FlagInfo>& table = tools::CommandFlagTable();
    std::vector<Flag> list;
#define NRSFM_PYTHON_FLAG(type, flag_name, value, role, bind, help)           \
  list.push_back({&table[list.size()], FlagType<type>::kName,                 \
                  [](const CommandFlags& f) {                                 \
                    return FlagType<type>::ToPython(f.flag_name);             \
                  },                                                          \
                  [](CommandFlags* f, py::handle v) {                         \
                    f->flag_name = FlagType<type>::FromPython(v, #flag_name); \
                  }});
    NRSFM_COMMAND_FLAGS(NRSFM_PYTHON_FLAG)
#undef NRSFM_PYTHON_FLAG
    for (std::size_t i = 0; i < ExtraTerms().size(); ++i) {
      const tools::FlagInfo* info = &table[list.size()];
      list.push_back({info, "float",
                      [i](const CommandFlags& f) {
                        return py::object(py::float_(f.term_weights[i]));
                      },
                      [i, name = info->name](CommandFlags* f, py::handle v) {
                        f->term_weights[i] =
                            FlagType<double>::FromPython(v, name);
                      }});
    }
    for (const Flag& flag : list)
      CHECK_EQ(flag.type, flag.info->type) << flag.name();
    return list;
  }();
  return flags;
}

FunctionOptions MakeOptions(tools::Command command,
                            std::set<tools::FlagRole> roles,
                            std::set<std::string> left_out = {}) {
  FunctionOptions options;
  options.command = command;
  for (const Flag& flag : Flags()) {
    if (!flag.info->Serves(command) || roles.count(flag.info->role) == 0)
      continue;
    if (left_out.count(flag.name()) > 0) continue;
    options.flags.push_back(&flag);
  }
  return options;
}

using Role = tools::FlagRole;

// reconstruct(W, K, mask, cameras, progress, observation_weights,
// **options): the options of the start, the prior rule and the choice of K,
// of the problem and of the solver.
const FunctionOptions& ReconstructOptionsOf() {
  static const FunctionOptions options =
      MakeOptions(tools::kReconstruct, {Role::kStart, Role::kOption});
  return options;
}

// refine: the options of the problem and the solver.
const FunctionOptions& RefineOptionsOf() {
  static const FunctionOptions options =
      MakeOptions(tools::kReconstruct, {Role::kOption});
  return options;
}

// read(path, **options): how reconstruct and view read their input.
const FunctionOptions& ReadOptionsOf() {
  static const FunctionOptions options =
      MakeOptions(tools::kReconstruct, {Role::kInput});
  return options;
}

// synth(**options): every synth flag; output optional (writes the .mat).
const FunctionOptions& SynthOptionsOf() {
  static const FunctionOptions options =
      MakeOptions(tools::kSynth,
                  {Role::kInput, Role::kWeights, Role::kNumBases, Role::kStart,
                   Role::kOption, Role::kSynthesis, Role::kTool});
  return options;
}

const FunctionOptions& TrackOptionsOf() {
  static const FunctionOptions options =
      MakeOptions(tools::kTrack, {Role::kTracking});
  return options;
}

// evaluate(truth, result, **options): what evaluate reads besides its
// arguments (truth_var).
const FunctionOptions& EvaluateOptionsOf() {
  static const FunctionOptions options =
      MakeOptions(tools::kEvaluate, {Role::kTool}, {"truth", "result"});
  return options;
}

// Sets `flags` from the keyword arguments; TypeError on a keyword that is
// not an option of `function`.
void ApplyKeywords(const FunctionOptions& options, const char* function,
                   const py::dict& kwargs, CommandFlags* flags,
                   const std::set<std::string>& handled) {
  for (const auto& [key, value] : kwargs) {
    const std::string name = py::str(key);
    if (handled.count(name) > 0) continue;
    const Flag* flag = nullptr;
    for (const Flag* candidate : options.flags) {
      if (candidate->name() == name) flag = candidate;
    }
    if (flag == nullptr) {
      throw py::type_error(std::string(function) +
                           "() got an unexpected keyword argument '" + name +
                           "'");
    }
    flag->set(flags, value);
  }
}

// "name: type = default\n    help" for each keyword, for the docstrings.
std::string KeywordDoc(const FunctionOptions& options) {
  const CommandFlags defaults;
  std::ostringstream doc;
  for (const Flag* flag : options.flags) {
    const std::string help = flag->info->HelpFor(options.command);
    // synth's K is an int here (a string flag in the tool).
    if (options.command == tools::kSynth && flag->name() == "K") {
      doc << "    K: int = None\n        " << help << "\n";
      continue;
    }
    doc << "    " << flag->name() << ": " << flag->type << " = "
        << std::string(py::repr(flag->get(defaults))) << "\n        " << help
        << "\n";
  }
  return doc.str();
}

// {name: {"type", "default", "help"}} of a function's keywords.
py::dict KeywordTable(const FunctionOptions& options) {
  const CommandFlags defaults;
  py::dict table;
  for (const Flag* flag : options.flags) {
    py::dict entry;
    entry["type"] = flag->type;
    entry["default"] = flag->get(defaults);
    entry["help"] = flag->info->HelpFor(options.command);
    table[py::str(flag->name())] = entry;
  }
  return table;
}

}  // namespace python
}  // namespace nrsfm
