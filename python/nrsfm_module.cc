// The Python module `nrsfm` (pybind11): reconstruct, refine, read, evaluate
// and synth on numpy arrays, with the nrsfm tool's options and messages
// (tools/flag_options.h; the keywords are the tool's flags, from
// NRSFM_COMMAND_FLAGS and the extra-term table).
//
// Conventions (docs/guide.md, "Python"):
//   W        (2FM, P), rows u, v of frame t, camera c at 2(tM + c) and
//            2(tM + c) + 1 (core/measurements.h); NaN = missing.
//   mask     (FM, P) or (2FM, P), nonzero = visible.
//   rotations (F, M, 3, 3) R_tc (camera from object); translations (F, M, 2);
//   scales (F, M); weights (F, K); basis (K, 3, P); rig_rotations
//   (M − 1, 3, 3); rig_scales (M − 1,); points_camera (F, M, 3, P)
//   X_tc = s_tc R_tc S_t; points_object (F, 3, P) S_t.
// Inputs are any array-like convertible to float64, in any memory order or
// strides: they are copied element by element by index. Outputs are new
// C-contiguous float64 arrays that own their data.
// Bad input raises ValueError (OSError subclasses for a file that cannot be
// opened) with the tool's message; wrong keyword names or types TypeError.
// The solve runs without the GIL; the progress callback and a check for
// signals (Ctrl-C) run once per Levenberg–Marquardt iteration with it.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>
#include <glog/logging.h>

#include "core/ground_truth.h"
#include "core/mat_io.h"
#include "core/metrics.h"
#include "core/read_measurements.h"
#include "core/result_reader.h"
#include "core/result_writer.h"
#include "core/rotation.h"
#include "problems/extra_terms.h"
#include "solvers/refine.h"
#include "tools/command_flags.h"
#include "tools/flag_options.h"

namespace py = pybind11;

namespace nrsfm {
namespace python {
namespace {

using tools::CommandFlags;

// ---------------------------------------------------------------------------
// Errors.

// A Status error as ValueError with its message.
[[noreturn]] void ThrowValueError(const std::string& message) {
  throw py::value_error(message);
}

void Check(const Status& status) {
  if (!status.ok()) ThrowValueError(status.message());
}

// A failed read of `path`: an OSError subclass when the path cannot be
// opened as a file (missing, a directory, no permission), ValueError when
// the file's contents are at fault. The message is the tool's.
[[noreturn]] void ThrowFileError(const std::string& path, const Status& status,
                                 bool directory_allowed = false) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status file = fs::status(path, ec);
  PyObject* type = nullptr;
  if (!fs::exists(file)) {
    type = PyExc_FileNotFoundError;
  } else if (fs::is_directory(file) && !directory_allowed) {
    type = PyExc_IsADirectoryError;
  } else if (!fs::is_directory(file)) {
    FILE* f = std::fopen(path.c_str(), "rb");
    if (f == nullptr) {
      type = PyExc_PermissionError;
    } else {
      std::fclose(f);
    }
  }
  if (type == nullptr) ThrowValueError(status.message());
  PyErr_SetString(type, status.message().c_str());
  throw py::error_already_set();
}

// A filesystem path from str or os.PathLike.
std::string PathOf(py::handle object, const char* what) {
  if (py::isinstance<py::str>(object)) return object.cast<std::string>();
  PyObject* path = PyOS_FSPath(object.ptr());
  if (path == nullptr) {
    PyErr_Clear();
    throw py::type_error(std::string(what) + " must be a path (str or os.PathLike), got " +
                         std::string(py::str(py::type::of(object).attr("__name__"))));
  }
  py::object owned = py::reinterpret_steal<py::object>(path);
  if (!py::isinstance<py::str>(owned)) {
    throw py::type_error(std::string(what) + " must be a str path");
  }
  return owned.cast<std::string>();
}

bool IsPath(py::handle object) {
  return py::isinstance<py::str>(object) || py::hasattr(object, "__fspath__");
}

// ---------------------------------------------------------------------------
// Keyword options: the tool's flags.

template <typename T>
struct FlagType;

template <>
struct FlagType<std::string> {
  static constexpr const char* kName = "str";
  static py::object ToPython(const std::string& value) { return py::str(value); }
  static std::string FromPython(py::handle value, const std::string& name) {
    if (!py::isinstance<py::str>(value)) {
      throw py::type_error(name + " must be a str, got " +
                           std::string(py::str(py::type::of(value).attr("__name__"))));
    }
    return value.cast<std::string>();
  }
};

// An integer argument: a Python int or numpy integer, not a bool.
long long IntegerFromPython(py::handle value, const std::string& name) {
  if (py::isinstance<py::bool_>(value) || !PyIndex_Check(value.ptr())) {
    throw py::type_error(name + " must be an int, got " +
                         std::string(py::str(py::type::of(value).attr("__name__"))));
  }
  py::int_ index = py::reinterpret_steal<py::int_>(PyNumber_Index(value.ptr()));
  int overflow = 0;
  const long long result = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
  if (overflow != 0) throw py::value_error(name + " is out of range");
  return result;
}

template <>
struct FlagType<int> {
  static constexpr const char* kName = "int";
  static py::object ToPython(int value) { return py::int_(value); }
  static int FromPython(py::handle value, const std::string& name) {
    const long long v = IntegerFromPython(value, name);
    if (v < -1000000000LL || v > 1000000000LL) {
      throw py::value_error(name + " is out of range, got " + std::to_string(v));
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
      throw py::type_error(name + " must be an int, got " +
                           std::string(py::str(py::type::of(value).attr("__name__"))));
    }
    py::int_ index = py::reinterpret_steal<py::int_>(PyNumber_Index(value.ptr()));
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
      throw py::type_error(name + " must be a float, got " +
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
      throw py::type_error(name + " must be a bool, got " +
                           std::string(py::str(py::type::of(value).attr("__name__"))));
    }
    return value.cast<bool>();
  }
};

struct Flag {
  std::string name;
  std::string type;  // "int", "float", "str", "bool"
  std::string help;  // as in NRSFM_COMMAND_FLAGS (all commands)
  std::function<py::object(const CommandFlags&)> get;
  std::function<void(CommandFlags*, py::handle)> set;
};

// Every flag of the tool, in --help order, then one per extra term.
const std::vector<Flag>& Flags() {
  static const std::vector<Flag> flags = [] {
    std::vector<Flag> list;
#define NRSFM_PYTHON_FLAG(type, flag_name, value, flag_help)                       \
  list.push_back({#flag_name, FlagType<type>::kName, flag_help,                   \
                  [](const CommandFlags& f) { return FlagType<type>::ToPython(f.flag_name); }, \
                  [](CommandFlags* f, py::handle v) {                               \
                    f->flag_name = FlagType<type>::FromPython(v, #flag_name);       \
                  }});
    NRSFM_COMMAND_FLAGS(NRSFM_PYTHON_FLAG)
#undef NRSFM_PYTHON_FLAG
    const std::vector<ExtraTerm>& terms = ExtraTerms();
    for (std::size_t i = 0; i < terms.size(); ++i) {
      list.push_back({terms[i].name, "float", tools::TermFlagHelp(terms[i]),
                      [i](const CommandFlags& f) {
                        return py::object(py::float_(f.term_weights[i]));
                      },
                      [i, name = std::string(terms[i].name)](CommandFlags* f, py::handle v) {
                        f->term_weights[i] = FlagType<double>::FromPython(v, name);
                      }});
    }
    return list;
  }();
  return flags;
}

const Flag* FindFlag(const std::string& name) {
  for (const Flag& flag : Flags()) {
    if (flag.name == name) return &flag;
  }
  return nullptr;
}

// The keyword options of each function: the flags of the tool's command,
// less those the function takes as its own arguments or that concern the
// tool's files and printing.
struct FunctionOptions {
  std::string command;                 // the tool's command whose flags apply
  std::set<std::string> left_out;      // flags that are not keywords here
  std::vector<const Flag*> flags;      // the keywords, in --help order
};

FunctionOptions MakeOptions(const std::string& command, std::set<std::string> left_out) {
  FunctionOptions options;
  options.command = command;
  options.left_out = std::move(left_out);
  for (const Flag& flag : Flags()) {
    if (options.left_out.count(flag.name) > 0) continue;
    if (tools::FlagHelpFor(flag.help, command).empty()) continue;
    options.flags.push_back(&flag);
  }
  return options;
}

// reconstruct(W, K, mask, cameras, progress, observation_weights,
// **options): every reconstruct flag that is an option of a reconstruction
// of arrays (tools::NotArrayReconstructFlags()).
const FunctionOptions& ReconstructOptionsOf() {
  static const FunctionOptions options =
      MakeOptions("reconstruct", tools::NotArrayReconstructFlags());
  return options;
}

// refine: what sets the problem and the solver; not the start (init, seed),
// the prior rule (priors: refine uses exactly the weights given) or the
// choice of K.
const FunctionOptions& RefineOptionsOf() {
  static const FunctionOptions options = [] {
    std::set<std::string> left_out = ReconstructOptionsOf().left_out;
    left_out.insert({"init", "seed", "priors", "K_max", "K_threshold"});
    return MakeOptions("reconstruct", left_out);
  }();
  return options;
}

// read(path, **options): how reconstruct and view read their input
// (tools::InputFlags(), in --help order).
const FunctionOptions& ReadOptionsOf() {
  static const FunctionOptions options = [] {
    FunctionOptions o;
    o.command = "reconstruct";
    for (const Flag& flag : Flags()) {
      if (tools::InputFlags().count(flag.name) > 0) o.flags.push_back(&flag);
    }
    return o;
  }();
  return options;
}

// synth(**options): every synth flag; output optional (writes the .mat).
const FunctionOptions& SynthOptionsOf() {
  static const FunctionOptions options = MakeOptions("synth", {});
  return options;
}

// evaluate(truth, result, **options).
const FunctionOptions& EvaluateOptionsOf() {
  static const FunctionOptions options = [] {
    FunctionOptions o;
    o.command = "evaluate";
    o.flags.push_back(FindFlag("truth_var"));
    return o;
  }();
  return options;
}

// Sets `flags` from the keyword arguments; TypeError on a keyword that is
// not an option of `function`.
void ApplyKeywords(const FunctionOptions& options, const char* function,
                   const py::dict& kwargs, CommandFlags* flags,
                   const std::set<std::string>& handled = {}) {
  for (const auto& [key, value] : kwargs) {
    const std::string name = py::str(key);
    if (handled.count(name) > 0) continue;
    const Flag* flag = nullptr;
    for (const Flag* candidate : options.flags) {
      if (candidate->name == name) flag = candidate;
    }
    if (flag == nullptr) {
      throw py::type_error(std::string(function) + "() got an unexpected keyword argument '" +
                           name + "'");
    }
    flag->set(flags, value);
  }
}

// "name: type = default\n    help" for each keyword, for the docstrings.
std::string KeywordDoc(const FunctionOptions& options) {
  const CommandFlags defaults;
  std::ostringstream doc;
  for (const Flag* flag : options.flags) {
    const std::string help = tools::FlagHelpFor(flag->help, options.command);
    // synth's K is an int here (a string flag in the tool).
    if (options.command == "synth" && flag->name == "K") {
      doc << "    K: int = None\n        " << help << "\n";
      continue;
    }
    doc << "    " << flag->name << ": " << flag->type << " = "
        << std::string(py::repr(flag->get(defaults))) << "\n        " << help << "\n";
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
    entry["help"] = tools::FlagHelpFor(flag->help, options.command);
    table[py::str(flag->name)] = entry;
  }
  return table;
}

// ---------------------------------------------------------------------------
// Arrays.

using Array = py::array_t<double, py::array::c_style>;

// Any array-like as float64 (a copy when it is not already float64; any
// order or strides). ValueError naming `name` when it cannot be.
py::array_t<double, py::array::forcecast> AsDoubleArray(py::handle object,
                                                         const std::string& name) {
  if (object.is_none()) ThrowValueError(name + " is None");
  py::array_t<double, py::array::forcecast> array;
  try {
    array = py::array_t<double, py::array::forcecast>::ensure(object);
  } catch (py::error_already_set&) {
    array = py::array_t<double, py::array::forcecast>();
  }
  if (!array) {
    PyErr_Clear();
    ThrowValueError(name + " must be an array of numbers (convertible to float64), got " +
                    std::string(py::str(py::type::of(object).attr("__name__"))));
  }
  return array;
}

std::string ShapeString(const py::array& array) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < array.ndim(); ++i) {
    s += (i ? ", " : "") + std::to_string(array.shape(i));
  }
  return s + (array.ndim() == 1 ? ",)" : ")");
}

// A 2-D array-like as an Eigen matrix, element (i, j) = array[i, j].
Eigen::MatrixXd ToMatrix(py::handle object, const std::string& name) {
  const auto array = AsDoubleArray(object, name);
  if (array.ndim() != 2) {
    ThrowValueError(name + " must be a 2-D array, got shape " + ShapeString(array));
  }
  const auto a = array.unchecked<2>();
  Eigen::MatrixXd m(a.shape(0), a.shape(1));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    for (py::ssize_t j = 0; j < a.shape(1); ++j) m(i, j) = a(i, j);
  }
  return m;
}

// An array of exactly `shape`, or ValueError naming it.
py::array_t<double, py::array::forcecast> WithShape(py::handle object, const std::string& name,
                                                    const std::vector<py::ssize_t>& shape) {
  const auto array = AsDoubleArray(object, name);
  bool same = array.ndim() == static_cast<py::ssize_t>(shape.size());
  for (std::size_t i = 0; same && i < shape.size(); ++i) same = array.shape(i) == shape[i];
  if (!same) {
    std::string expected = "(";
    for (std::size_t i = 0; i < shape.size(); ++i) {
      expected += (i ? ", " : "") + std::to_string(shape[i]);
    }
    expected += shape.size() == 1 ? ",)" : ")";
    ThrowValueError(name + " has shape " + ShapeString(array) + ", expected " + expected);
  }
  return array;
}

Array NewArray(const std::vector<py::ssize_t>& shape) { return Array(shape); }

// Measurements from W (2FM × P) and an optional mask, named "W" and "mask"
// in the messages.
Measurements MeasurementsOf(py::handle w_object, py::handle mask_object, int cameras) {
  const Eigen::MatrixXd w = ToMatrix(w_object, "W");
  const Eigen::MatrixXd mask =
      mask_object.is_none() ? Eigen::MatrixXd() : ToMatrix(mask_object, "mask");
  Measurements m;
  Check(tools::MeasurementsFromArrays(w, mask, cameras, &m));
  return m;
}

py::array WArray(const Measurements& m) {
  Array w = NewArray({2 * m.NumViews(), m.num_points});
  auto a = w.mutable_unchecked<2>();
  for (int i = 0; i < 2 * m.NumViews(); ++i) {
    for (int p = 0; p < m.num_points; ++p) {
      a(i, p) = m.visible(i / 2, p) ? m.W(i, p) : std::nan("");
    }
  }
  return std::move(w);
}

// The observation_weights argument (FM, P) as given, or empty for None
// (tools::ArrayReconstructOptions scales them).
Eigen::ArrayXXd ObservationWeightsOf(py::handle object) {
  if (object.is_none()) return Eigen::ArrayXXd();
  return ToMatrix(object, "observation_weights").array();
}

py::array MaskArray(const Measurements& m) {
  py::array_t<bool> mask({static_cast<py::ssize_t>(m.NumViews()),
                          static_cast<py::ssize_t>(m.num_points)});
  auto a = mask.mutable_unchecked<2>();
  for (int v = 0; v < m.NumViews(); ++v) {
    for (int p = 0; p < m.num_points; ++p) a(v, p) = m.visible(v, p);
  }
  return std::move(mask);
}

// ---------------------------------------------------------------------------
// Results.

// A reconstruction (or a model given to refine, or a synthetic truth): the
// model's blocks as arrays, the shapes they give, and what the solve said.
struct Reconstruction {
  py::object rotations, translations, scales, weights, basis, rig_rotations, rig_scales;
  py::object points_camera, points_object;
  py::dict summary;
  py::list dropped_points, dropped_frames;
};

Reconstruction FromModel(const Model& model) {
  const int f = model.num_frames, m = model.num_cameras, p = model.num_points,
            k = model.num_bases;
  Reconstruction r;
  Array rotations = NewArray({f, m, 3, 3}), translations = NewArray({f, m, 2}),
        scales = NewArray({f, m}), weights = NewArray({f, k}), basis = NewArray({k, 3, p}),
        rig_rotations = NewArray({m - 1, 3, 3}), rig_scales = NewArray({m - 1}),
        points_camera = NewArray({f, m, 3, p}), points_object = NewArray({f, 3, p});
  auto rot = rotations.mutable_unchecked<4>();
  auto tra = translations.mutable_unchecked<3>();
  auto sca = scales.mutable_unchecked<2>();
  auto pc = points_camera.mutable_unchecked<4>();
  auto po = points_object.mutable_unchecked<3>();
  auto wei = weights.mutable_unchecked<2>();
  for (int t = 0; t < f; ++t) {
    for (int c = 0; c < m; ++c) {
      const Eigen::Matrix3d r_tc = model.Rotation(t, c);
      const Eigen::Matrix3Xd x = model.ShapeInCamera(t, c);
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) rot(t, c, i, j) = r_tc(i, j);
        for (int q = 0; q < p; ++q) pc(t, c, i, q) = x(i, q);
      }
      for (int i = 0; i < 2; ++i) tra(t, c, i) = model.translations(i, model.View(t, c));
      sca(t, c) = model.scales(model.View(t, c));
    }
    const Eigen::Matrix3Xd s = model.ShapeInObject(t);
    for (int i = 0; i < 3; ++i) {
      for (int q = 0; q < p; ++q) po(t, i, q) = s(i, q);
    }
    for (int b = 0; b < k; ++b) wei(t, b) = model.weights(b, t);
  }
  auto bas = basis.mutable_unchecked<3>();
  for (int b = 0; b < k; ++b) {
    for (int i = 0; i < 3; ++i) {
      for (int q = 0; q < p; ++q) bas(b, i, q) = model.basis(3 * b + i, q);
    }
  }
  auto rig = rig_rotations.mutable_unchecked<3>();
  auto rig_s = rig_scales.mutable_unchecked<1>();
  for (int c = 0; c + 1 < m; ++c) {
    const Eigen::Matrix3d r = AngleAxisToRotation(model.rig_rotations.col(c));
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) rig(c, i, j) = r(i, j);
    }
    rig_s(c) = model.rig_scales(c);
  }
  r.rotations = rotations;
  r.translations = translations;
  r.scales = scales;
  r.weights = weights;
  r.basis = basis;
  r.rig_rotations = rig_rotations;
  r.rig_scales = rig_scales;
  r.points_camera = points_camera;
  r.points_object = points_object;
  return r;
}

// Attribute `name` of `object`, or key `name` of a mapping; None if absent.
py::object Field(py::handle object, const char* name) {
  if (py::isinstance<py::dict>(object)) {
    py::dict d = py::reinterpret_borrow<py::dict>(object);
    return d.contains(name) ? py::object(d[name]) : py::none();
  }
  return py::getattr(object, name, py::none());
}

// A model of F, M, P from `object` (a Reconstruction, any object with the
// attributes, or a dict): rotations, translations, weights, basis required;
// scales, rig_rotations, rig_scales optional (1, identity, 1).
Model ModelFromPython(py::handle object, const Measurements& m) {
  const int f = m.num_frames, cams = m.num_cameras, p = m.num_points;
  py::object weights_object = Field(object, "weights");
  if (weights_object.is_none()) {
    ThrowValueError("model must have rotations, translations, weights and basis "
                    "(attributes or keys)");
  }
  const auto weights_array = AsDoubleArray(weights_object, "model.weights");
  if (weights_array.ndim() != 2 || weights_array.shape(0) != f || weights_array.shape(1) < 1) {
    ThrowValueError("model.weights has shape " + ShapeString(weights_array) + ", expected (" +
                    std::to_string(f) + ", K) for the F = " + std::to_string(f) +
                    " frames of W");
  }
  const int k = static_cast<int>(weights_array.shape(1));
  Model model;
  model.Resize(f, cams, p, k);
  auto required = [&](const char* name) {
    py::object value = Field(object, name);
    if (value.is_none()) ThrowValueError(std::string("model has no ") + name);
    return value;
  };
  const auto rotations = WithShape(required("rotations"), "model.rotations", {f, cams, 3, 3});
  const auto translations = WithShape(required("translations"), "model.translations", {f, cams, 2});
  const auto basis = WithShape(required("basis"), "model.basis", {k, 3, p});
  auto rot = rotations.unchecked<4>();
  auto tra = translations.unchecked<3>();
  for (int t = 0; t < f; ++t) {
    for (int c = 0; c < cams; ++c) {
      Eigen::Matrix3d r;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) r(i, j) = rot(t, c, i, j);
      }
      const std::string where = "model.rotations[" + std::to_string(t) + ", " +
                                std::to_string(c) + "]";
      if (!r.allFinite()) {
        ThrowValueError(where + " is not finite (a reconstruction that left frames out "
                                "holds NaN there; refine needs a finite model)");
      }
      if ((r * r.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6 ||
          r.determinant() < 0.0) {
        ThrowValueError(where + " is not a rotation matrix (R R^T = I and det R = +1 to 1e-6)");
      }
      model.SetRotation(t, c, r);
      for (int i = 0; i < 2; ++i) model.translations(i, model.View(t, c)) = tra(t, c, i);
    }
  }
  auto wei = weights_array.unchecked<2>();
  for (int t = 0; t < f; ++t) {
    for (int b = 0; b < k; ++b) model.weights(b, t) = wei(t, b);
  }
  auto bas = basis.unchecked<3>();
  for (int b = 0; b < k; ++b) {
    for (int i = 0; i < 3; ++i) {
      for (int q = 0; q < p; ++q) model.basis(3 * b + i, q) = bas(b, i, q);
    }
  }
  py::object scales = Field(object, "scales");
  if (!scales.is_none()) {
    const auto s = WithShape(scales, "model.scales", {f, cams});
    auto a = s.unchecked<2>();
    for (int t = 0; t < f; ++t) {
      for (int c = 0; c < cams; ++c) model.scales(model.View(t, c)) = a(t, c);
    }
  }
  py::object rig_rotations = Field(object, "rig_rotations");
  if (!rig_rotations.is_none()) {
    const auto r = WithShape(rig_rotations, "model.rig_rotations", {cams - 1, 3, 3});
    auto a = r.unchecked<3>();
    for (int c = 0; c + 1 < cams; ++c) {
      Eigen::Matrix3d m3;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) m3(i, j) = a(c, i, j);
      }
      if (!m3.allFinite() ||
          (m3 * m3.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6 ||
          m3.determinant() < 0.0) {
        ThrowValueError("model.rig_rotations[" + std::to_string(c) +
                        "] is not a rotation matrix");
      }
      model.rig_rotations.col(c) = RotationToAngleAxis(m3);
    }
  }
  py::object rig_scales = Field(object, "rig_scales");
  if (!rig_scales.is_none()) {
    const auto s = WithShape(rig_scales, "model.rig_scales", {cams - 1});
    auto a = s.unchecked<1>();
    for (int c = 0; c + 1 < cams; ++c) model.rig_scales(c) = a(c);
  }
  Check(model.Validate().WithContext("refine"));
  return model;
}

// ---------------------------------------------------------------------------
// The solve: progress callback, signals, warnings.

// Runs `solve` without the GIL. Once per LM iteration the GIL is taken to
// call `progress(iteration, cost, seconds)` (if not None) and to check for
// signals; an exception from either (KeyboardInterrupt on Ctrl-C) asks the
// solver to stop and is raised when the solve has returned.
class Interruptible {
 public:
  explicit Interruptible(py::object progress) : progress_(std::move(progress)) {
    if (!progress_.is_none() && !PyCallable_Check(progress_.ptr())) {
      throw py::type_error("progress must be callable (iteration, cost, seconds) or None");
    }
  }

  void Configure(SolverOptions* solver) {
    solver->progress = [this](const IterationReport& report) { OnIteration(report); };
    solver->stop_requested = [this] { return stop_.load(); };
  }

  template <typename Function>
  Status Run(Function&& solve) {
    Status status;
    {
      py::gil_scoped_release release;
      status = solve();
    }
    if (error_) {
      error_->restore();
      error_.reset();
      throw py::error_already_set();
    }
    return status;
  }

 private:
  void OnIteration(const IterationReport& report) {
    if (stop_) return;
    py::gil_scoped_acquire acquire;
    try {
      if (!progress_.is_none()) progress_(report.iteration, report.cost, report.seconds);
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    } catch (py::error_already_set& e) {
      error_.emplace(std::move(e));
      stop_ = true;
    }
  }

  py::object progress_;
  std::atomic<bool> stop_{false};
  std::optional<py::error_already_set> error_;
};

py::object NrsfmWarning() {
  static py::object* type = nullptr;
  if (type == nullptr) {
    type = new py::object(py::reinterpret_steal<py::object>(
        PyErr_NewExceptionWithDoc("nrsfm.NrsfmWarning",
                                  "Warnings of nrsfm about a result: points or frames left "
                                  "out, little rotation, an unusable refinement.",
                                  PyExc_UserWarning, nullptr)));
  }
  return *type;
}

void Warn(const std::vector<std::string>& warnings) {
  for (const std::string& warning : warnings) {
    if (PyErr_WarnEx(NrsfmWarning().ptr(), warning.c_str(), 2) != 0) {
      throw py::error_already_set();
    }
  }
}

// ValueError(message) with .result = `result`: an unusable refinement.
[[noreturn]] void ThrowUnusable(const std::string& message, py::object result) {
  py::object error = py::module_::import("builtins").attr("ValueError")(message);
  error.attr("result") = result;
  PyErr_SetObject(PyExc_ValueError, error.ptr());
  throw py::error_already_set();
}

py::dict JsonToDict(const std::string& text) {
  return py::module_::import("json").attr("loads")(text);
}

// ---------------------------------------------------------------------------
// The functions.

Reconstruction Reconstruct(py::handle w, py::handle k, py::handle mask, int cameras,
                           py::object progress, py::handle observation_weights,
                           const py::kwargs& kwargs) {
  CommandFlags flags;
  ApplyKeywords(ReconstructOptionsOf(), "reconstruct", kwargs, &flags);
  if (py::isinstance<py::str>(k)) {
    flags.K = k.cast<std::string>();
  } else {
    flags.K = std::to_string(IntegerFromPython(k, "K"));
  }
  flags.cameras = cameras;
  bool auto_k = false;
  int num_bases = 0;
  Check(tools::ParseNumBasesFlag(flags.K, &auto_k, &num_bases));
  ReconstructOptions options;
  Check(tools::BuildReconstructOptions(flags, &options));
  const Measurements measurements = MeasurementsOf(w, mask, cameras);
  Check(tools::ArrayReconstructOptions(measurements, ObservationWeightsOf(observation_weights),
                                       &flags, &options));

  Interruptible interruptible(std::move(progress));
  interruptible.Configure(&options.solver);
  tools::ReconstructionRun run;
  Check(interruptible.Run([&] {
    return tools::RunReconstruction(flags, options, measurements, "", &run);
  }));

  const ReconstructionReport report = tools::MakeReport(flags, "", run, nullptr);
  Reconstruction result = FromModel(run.result.model);
  result.summary = JsonToDict(ReconstructionJson(measurements, run.result.model, report));
  if (run.auto_k) {
    py::list curve;
    for (const NumBasesCandidate& c : run.selection.curve) {
      py::dict entry;
      entry["K"] = c.num_bases;
      entry["ok"] = c.ok;
      entry["message"] = c.message;
      entry["reprojection_rms"] = c.reprojection_rms;
      entry["expected_rms"] = c.expected_rms;
      entry["seconds"] = c.seconds;
      curve.append(entry);
    }
    py::dict selection;
    selection["noise_stddev"] = run.selection.noise_stddev;
    selection["curve"] = curve;
    result.summary["K_selection"] = selection;
  }
  result.dropped_points = py::cast(run.result.dropped_points);
  result.dropped_frames = py::cast(run.result.dropped_frames);
  Warn(report.warnings);
  if (!run.result.refine.usable) {
    ThrowUnusable("the refinement did not give a usable solution (" +
                      run.result.refine.message +
                      "); the exception's .result holds the start, marked "
                      "solution_usable = false",
                  py::cast(result));
  }
  return result;
}

Reconstruction Refine(py::handle w, py::handle model_object, py::handle mask, int cameras,
                      py::object progress, py::handle observation_weights,
                      const py::kwargs& kwargs) {
  CommandFlags flags;
  ApplyKeywords(RefineOptionsOf(), "refine", kwargs, &flags);
  flags.cameras = cameras;
  ReconstructOptions options;
  Check(tools::BuildReconstructOptions(flags, &options));
  const Measurements measurements = MeasurementsOf(w, mask, cameras);
  Check(tools::ArrayReconstructOptions(measurements, ObservationWeightsOf(observation_weights),
                                       &flags, &options));
  Model model = ModelFromPython(model_object, measurements);

  Interruptible interruptible(std::move(progress));
  interruptible.Configure(&options.solver);
  RefineSummary summary;
  Check(interruptible.Run([&] {
    return nrsfm::Refine(options.problem, options.solver, measurements, &model, &summary);
  }));
  Reconstruction result = FromModel(model);
  py::dict s;
  s["usable"] = summary.usable;
  s["converged"] = summary.converged;
  s["stopped"] = summary.stopped;
  s["message"] = summary.message;
  s["initial_cost"] = summary.initial_cost;
  s["final_cost"] = summary.final_cost;
  s["initial_reprojection_rms"] = summary.initial_reprojection_rms;
  s["reprojection_rms"] = summary.reprojection_rms;
  s["iterations"] = summary.iterations;
  s["num_residual_blocks"] = summary.num_residual_blocks;
  s["linear_solver"] = summary.linear_solver;
  s["seconds"] = summary.seconds;
  py::dict weights;
  for (const auto& [name, weight] : options.problem.term_weights) weights[py::str(name)] = weight;
  s["term_weights"] = weights;
  py::dict used;
  const CommandFlags& f = flags;
  for (const Flag* flag : RefineOptionsOf().flags) used[py::str(flag->name)] = flag->get(f);
  s["options"] = used;
  s["observation_weights"] = options.problem.observation_weights.size() > 0;
  result.summary = s;
  if (!summary.usable) {
    ThrowUnusable("the refinement did not give a usable solution (" + summary.message +
                      "); the exception's .result holds the model given, unchanged",
                  py::cast(result));
  }
  return result;
}

struct Tracks {
  py::object W, mask;
  int cameras = 1;
  // read: the file's index of each frame and point when the reader
  // renumbered them (core/text_io.h, a sparse observation list); else None.
  py::object frame_ids = py::none();
  py::object point_ids = py::none();
  // read() of a keypoint input: the detector's score of each keypoint,
  // (FM, P), NaN in frames with no person; else None.
  py::object confidence = py::none();
  py::object truth = py::none();  // synth: a Reconstruction of the truth
  py::object P3_gt = py::none();  // synth: camera 0's truth, (3F, P) block layout
};

Tracks TracksOf(const Measurements& m) {
  Tracks tracks;
  tracks.W = WArray(m);
  tracks.mask = MaskArray(m);
  tracks.cameras = m.num_cameras;
  if (!m.frame_ids.empty()) tracks.frame_ids = py::cast(m.frame_ids);
  if (!m.point_ids.empty()) tracks.point_ids = py::cast(m.point_ids);
  return tracks;
}

Tracks Read(py::handle path_object, const py::kwargs& kwargs) {
  const std::string path = PathOf(path_object, "path");
  CommandFlags flags;
  ApplyKeywords(ReadOptionsOf(), "read", kwargs, &flags);
  if (flags.cameras < 0) {
    ThrowValueError("--cameras must be >= 1 (or 0: from the file), got " +
                    std::to_string(flags.cameras));
  }
  InputOptions input;
  Check(tools::BuildInputOptions(flags, &input));
  Measurements m;
  InputDetails details;
  const Status status = ReadMeasurements(path, input, &m, &details);
  // A folder is an input (OpenPose's) unless a file's format is asked for.
  const std::string extension = std::filesystem::path(path).extension().string();
  const bool folder_input = input.format == InputFormat::kOpenPose ||
                            (input.format == InputFormat::kAuto && extension != ".mat");
  if (!status.ok()) ThrowFileError(path, status, folder_input);
  Tracks tracks = TracksOf(m);
  if (details.confidence.size() > 0) {
    Array confidence = NewArray({details.confidence.rows(), details.confidence.cols()});
    auto a = confidence.mutable_unchecked<2>();
    for (Eigen::Index i = 0; i < details.confidence.rows(); ++i) {
      for (Eigen::Index j = 0; j < details.confidence.cols(); ++j) {
        a(i, j) = details.confidence(i, j);
      }
    }
    tracks.confidence = confidence;
  }
  Warn(details.warnings);
  return tracks;
}

Tracks Synth(const py::kwargs& kwargs) {
  CommandFlags flags;
  // K: an int (or None, the generator's default) here, a string flag in
  // the tool.
  ApplyKeywords(SynthOptionsOf(), "synth", kwargs, &flags, {"K"});
  if (kwargs.contains("K")) {
    py::object k = kwargs["K"];
    if (py::isinstance<py::str>(k)) {
      flags.K = k.cast<std::string>();
    } else if (!k.is_none()) {
      flags.K = std::to_string(IntegerFromPython(k, "K"));
    }
  }
  if (!flags.output.empty()) Check(tools::CheckSynthOutput(flags.output));
  if (flags.dataset == "reproject") {
    // Its truth is an object frame with rotations (S + Rs), read back from
    // the file by evaluate(), so the file is needed.
    if (flags.output.empty()) {
      ThrowValueError("synth: dataset 'reproject' needs output= (a .mat path): its truth "
                      "(S and Rs) is scored from that file");
    }
    ReprojectedSequence reprojected;
    std::vector<MatVariable> variables;
    Check(tools::SynthesizeReprojection(flags, &reprojected, &variables));
    const Status status = WriteMat(flags.output, MatVersion::kV5, variables);
    if (!status.ok()) ThrowFileError(flags.output, status);
    Tracks tracks = TracksOf(reprojected.measurements);
    tracks.truth = py::str(flags.output);
    return tracks;
  }
  SyntheticSequence sequence;
  Check(tools::Synthesize(flags, &sequence));
  const std::vector<MatVariable> variables = tools::SyntheticVariables(sequence);
  if (!flags.output.empty()) {
    const Status status = WriteMat(flags.output, MatVersion::kV5, variables);
    if (!status.ok()) ThrowFileError(flags.output, status);
  }
  Tracks tracks = TracksOf(sequence.measurements);
  Reconstruction truth = FromModel(sequence.truth);
  truth.summary["dataset"] = flags.dataset;
  tracks.truth = py::cast(truth);
  for (const MatVariable& variable : variables) {
    if (variable.name != "P3_gt") continue;
    Array p3 = NewArray({variable.value.rows(), variable.value.cols()});
    auto a = p3.mutable_unchecked<2>();
    for (Eigen::Index i = 0; i < variable.value.rows(); ++i) {
      for (Eigen::Index j = 0; j < variable.value.cols(); ++j) a(i, j) = variable.value(i, j);
    }
    tracks.P3_gt = p3;
  }
  return tracks;
}

// Shapes (F, 3, P) as a camera-frame GroundTruth.
std::vector<Eigen::Matrix3Xd> ShapesOf(py::handle object, const std::string& name) {
  const auto array = AsDoubleArray(object, name);
  if (array.ndim() != 3 || array.shape(1) != 3) {
    ThrowValueError(name + " has shape " + ShapeString(array) + ", expected (F, 3, P)");
  }
  const auto a = array.unchecked<3>();
  std::vector<Eigen::Matrix3Xd> shapes;
  for (py::ssize_t t = 0; t < a.shape(0); ++t) {
    Eigen::Matrix3Xd x(3, a.shape(2));
    for (int i = 0; i < 3; ++i) {
      for (py::ssize_t p = 0; p < a.shape(2); ++p) x(i, p) = a(t, i, p);
    }
    shapes.push_back(x);
  }
  return shapes;
}

// Camera 0 of points_camera (F, M, 3, P).
std::vector<Eigen::Matrix3Xd> CameraZeroOf(py::handle object, const std::string& name) {
  const auto array = AsDoubleArray(object, name);
  if (array.ndim() != 4 || array.shape(1) < 1 || array.shape(2) != 3) {
    ThrowValueError(name + " has shape " + ShapeString(array) + ", expected (F, M, 3, P)");
  }
  py::object first = array[py::make_tuple(py::slice(py::none(), py::none(), py::none()), 0)];
  return ShapesOf(first, name + "[:, 0]");
}

// The truth or the estimate of evaluate: a path (as --truth / --result), an
// array (F, 3, P) of camera-frame shapes, or an object with points_camera
// (and, for the estimate, points_object and rotations: its object frame).
GroundTruth ShapesForEvaluation(py::handle object, bool is_truth, const std::string& variable) {
  GroundTruth shapes;
  if (IsPath(object)) {
    const std::string path = PathOf(object, is_truth ? "truth" : "result");
    Status status;
    std::error_code ec;
    if (is_truth) {
      status = tools::ReadTruth(path, variable, &shapes);
    } else if (std::filesystem::is_directory(path, ec)) {
      status = ReadResultShapes(path, /*camera=*/0, &shapes);
    } else {
      status = ReadPointsCameraCsv(path, /*camera=*/0, &shapes);
    }
    if (!status.ok()) ThrowFileError(path, status, /*directory_allowed=*/true);
    return shapes;
  }
  const std::string name = is_truth ? "truth" : "result";
  // The Tracks of synth carry their truth.
  if (is_truth && py::isinstance<Tracks>(object)) {
    py::object truth = object.cast<const Tracks&>().truth;
    if (truth.is_none()) ThrowValueError("truth: these Tracks have no truth (only synth's do)");
    return ShapesForEvaluation(truth, is_truth, variable);
  }
  if (py::hasattr(object, "points_camera") || py::isinstance<py::dict>(object)) {
    py::object points_camera = Field(object, "points_camera");
    if (points_camera.is_none()) ThrowValueError(name + " has no points_camera");
    shapes.points_in_camera = CameraZeroOf(points_camera, name + ".points_camera");
    shapes.source = "points_camera";
    py::object points_object = Field(object, "points_object");
    py::object rotations = Field(object, "rotations");
    if (!is_truth && !points_object.is_none() && !rotations.is_none()) {
      shapes.points_in_object = ShapesOf(points_object, name + ".points_object");
      const auto r = AsDoubleArray(rotations, name + ".rotations");
      if (r.ndim() != 4 || r.shape(0) != static_cast<py::ssize_t>(shapes.points_in_camera.size()) ||
          r.shape(1) < 1 || r.shape(2) != 3 || r.shape(3) != 3) {
        ThrowValueError(name + ".rotations has shape " + ShapeString(r) + ", expected (" +
                        std::to_string(shapes.points_in_camera.size()) + ", M, 3, 3)");
      }
      auto a = r.unchecked<4>();
      for (py::ssize_t t = 0; t < a.shape(0); ++t) {
        Eigen::Matrix3d m;
        for (int i = 0; i < 3; ++i) {
          for (int j = 0; j < 3; ++j) m(i, j) = a(t, 0, i, j);
        }
        shapes.rotations.push_back(m);
      }
      shapes.source = "result";
    }
    return shapes;
  }
  shapes.points_in_camera = ShapesOf(object, name);
  shapes.source = "array";
  return shapes;
}

py::dict Evaluate(py::handle truth_object, py::handle result_object, const py::kwargs& kwargs) {
  CommandFlags flags;
  ApplyKeywords(EvaluateOptionsOf(), "evaluate", kwargs, &flags);
  const GroundTruth truth = ShapesForEvaluation(truth_object, true, flags.truth_var);
  const GroundTruth estimate = ShapesForEvaluation(result_object, false, "");
  ShapeErrors errors;
  Check(EvaluateShapes(truth, estimate, &errors));
  // The rank-K floor beside an object-frame e3D, K from a result's weights.
  int num_bases = 0;
  double floor = -1.0;
  if (errors.e3d_frame == EvaluationFrame::kObject && py::hasattr(result_object, "weights")) {
    const py::array weights = py::array::ensure(result_object.attr("weights"));
    if (weights && weights.ndim() == 2 && weights.shape(1) >= 1) {
      num_bases = static_cast<int>(weights.shape(1));
      floor = ComputeRankFloorE3D(truth.points_in_object, num_bases);
    }
  }
  return JsonToDict(tools::EvaluationJson(errors, num_bases, floor));
}

// ---------------------------------------------------------------------------
// Docstrings.

constexpr char kConventions[] = R"(
Array conventions (F frames, M cameras, P points, K basis shapes):
    W             (2FM, P)  rows 2(tM + c), 2(tM + c) + 1 = u, v of frame t,
                            camera c; NaN = missing (both coordinates)
    mask          (FM, P) or (2FM, P), nonzero = visible
    rotations     (F, M, 3, 3)  R_tc, camera from object
    translations  (F, M, 2)     T_tc, image units
    scales        (F, M)        s_tc (camera 0: 1)
    weights       (F, K)        l_tk
    basis         (K, 3, P)     S_k
    rig_rotations (M - 1, 3, 3), rig_scales (M - 1,)  the fixed rig
    points_camera (F, M, 3, P)  X_tc = s_tc R_tc S_t (no translation)
    points_object (F, 3, P)     S_t = sum_k l_tk S_k
so that W[2(tM + c):2(tM + c) + 2] = points_camera[t, c, :2] + T_tc[:, None].
Inputs may be any array-like convertible to float64 in any memory order;
they are copied. Outputs are new C-contiguous float64 arrays.
)";

std::string ReconstructDoc() {
  return "reconstruct(W, K, mask=None, cameras=1, progress=None, observation_weights=None,\n"
         "            **options) -> Reconstruction\n"
         "\n"
         "The closed-form start and its Ceres refinement, as `nrsfm reconstruct`\n"
         "(README.md, docs/priors.md). K is an int >= 1 or 'auto'. progress, if given,\n"
         "is called as progress(iteration, cost, seconds) once per Levenberg-Marquardt\n"
         "iteration; an exception it raises (and Ctrl-C) stops the solve and is raised.\n"
         "The solve runs without the GIL.\n"
         "observation_weights, if given, (FM, P): relative weights of the observations'\n"
         "residuals (e.g. read()'s confidence of a keypoint input, as the tool's\n"
         "--confidence_weights), scaled to average 1 over the visible observations.\n"
         "\n"
         "Returns a Reconstruction: the arrays below, summary (the dict nrsfm writes as\n"
         "result.json, plus K_selection with K = 'auto'), dropped_points and\n"
         "dropped_frames (left out for too few observations: NaN in the arrays).\n"
         "Warnings (points left out, little rotation) are issued as NrsfmWarning.\n"
         "Raises ValueError with the tool's message on bad input; when the refinement\n"
         "is not usable, ValueError whose .result holds the start.\n"
         "\n"
         "Keyword options (the tool's flags, same names and defaults):\n" +
         KeywordDoc(ReconstructOptionsOf()) + kConventions;
}

std::string RefineDoc() {
  return "refine(W, model, mask=None, cameras=1, progress=None, observation_weights=None,\n"
         "       **options) -> Reconstruction\n"
         "\n"
         "Levenberg-Marquardt refinement of a model of your own (the library's Refine(),\n"
         "solvers/refine.h) against W, with exactly the term weights given. model is a\n"
         "Reconstruction, any object with the attributes, or a dict: rotations,\n"
         "translations, weights, basis required; scales, rig_rotations, rig_scales\n"
         "optional (1, identity, 1); shapes as below. The model given is not changed.\n"
         "progress, Ctrl-C and observation_weights as for reconstruct. summary: usable,\n"
         "converged, stopped,\n"
         "message, costs, reprojection RMS, iterations, linear solver, seconds.\n"
         "Raises ValueError on bad input, and whose .result holds the model given when\n"
         "the refinement is not usable.\n"
         "\n"
         "Keyword options:\n" +
         KeywordDoc(RefineOptionsOf()) + kConventions;
}

std::string ReadDoc() {
  return "read(path, **options) -> Tracks\n"
         "\n"
         "Reads measurements as `nrsfm reconstruct --input` does: .mat v4/v5/v7.3 (W,\n"
         "P3_gt or X), text/CSV W, observation list (.obs/.list), COCO keypoint results\n"
         "(.json) or a folder of OpenPose .json frames (pixels, v down). Returns Tracks\n"
         "with W (2FM, P, NaN = missing), mask (FM, P, bool), cameras (M) and, for\n"
         "keypoints, confidence (FM, P; the detector's scores, NaN in frames with no\n"
         "person); what the file's frames lack (no person) is issued as NrsfmWarning.\n"
         "Raises OSError\n"
         "(FileNotFoundError, IsADirectoryError, PermissionError) when the file cannot be\n"
         "opened, ValueError when its contents are at fault.\n"
         "\n"
         "Keyword options:\n" +
         KeywordDoc(ReadOptionsOf());
}

std::string SynthDoc() {
  return "synth(**options) -> Tracks\n"
         "\n"
         "A synthetic sequence, as `nrsfm synth` (core/synthetic.h): Tracks with W, mask,\n"
         "cameras, truth (a Reconstruction of the generating model) and P3_gt (camera\n"
         "0's truth with translations, (3F, P), rows x of every frame, then y, then z).\n"
         "With output='PATH.mat' the same .mat file as the tool is written too.\n"
         "\n"
         "Keyword options:\n" +
         KeywordDoc(SynthOptionsOf());
}

std::string EvaluateDoc() {
  return "evaluate(truth, result, **options) -> dict\n"
         "\n"
         "The metrics of `nrsfm evaluate` (core/metrics.h, docs/metrics.md), the same\n"
         "dict as its JSON line: e3d, e3d_camera, frob_zsign, error3d_pct, zerror_pct,\n"
         "rotation_error (when both have rotations), e3d_frame, F, P, and\n"
         "unscored_frames / unscored_points when the result holds NaN there.\n"
         "truth: a path as --truth (.mat with S + Rs, P3_gt or X; a result directory),\n"
         "an array (F, 3, P) of camera-frame shapes, an object with points_camera\n"
         "(camera 0), or the Tracks of synth (their truth). result: a result directory or points_camera.csv, an array\n"
         "(F, 3, P), or a Reconstruction (camera 0 and its object frame, so a truth\n"
         "with S + Rs is scored in the object frame, as the tool does).\n"
         "\n"
         "Keyword options:\n" +
         KeywordDoc(EvaluateOptionsOf());
}

// The docstrings live as long as the module.
const char* Keep(std::string text) {
  static std::vector<std::unique_ptr<std::string>> kept;
  kept.push_back(std::make_unique<std::string>(std::move(text)));
  return kept.back()->c_str();
}

}  // namespace
}  // namespace python
}  // namespace nrsfm

PYBIND11_MODULE(nrsfm, m) {
  using namespace nrsfm::python;
  // Each docstring starts with its Python signature.
  py::options options;
  options.disable_function_signatures();
  // The library logs through glog: to stderr, never into files.
  FLAGS_logtostderr = true;
  m.doc() = Keep(std::string(
      "nrsfm: non-rigid structure from motion (docs/guide.md, \"Python\").\n\n"
      "reconstruct, refine, read, evaluate and synth, with the nrsfm tool's options\n"
      "as keywords (same names and defaults; OPTIONS lists them) and its messages.\n") +
      kConventions);
  m.attr("__version__") = NRSFM_VERSION;

  py::class_<Reconstruction>(m, "Reconstruction",
                             "A model as arrays (see the module's array conventions), the "
                             "shapes it gives, and the summary of the solve.")
      .def_readonly("rotations", &Reconstruction::rotations, "(F, M, 3, 3) R_tc")
      .def_readonly("translations", &Reconstruction::translations, "(F, M, 2) T_tc")
      .def_readonly("scales", &Reconstruction::scales, "(F, M) s_tc")
      .def_readonly("weights", &Reconstruction::weights, "(F, K) l_tk")
      .def_readonly("basis", &Reconstruction::basis, "(K, 3, P) S_k")
      .def_readonly("rig_rotations", &Reconstruction::rig_rotations, "(M - 1, 3, 3)")
      .def_readonly("rig_scales", &Reconstruction::rig_scales, "(M - 1,)")
      .def_readonly("points_camera", &Reconstruction::points_camera,
                    "(F, M, 3, P) X_tc = s_tc R_tc S_t, computed when the result was made")
      .def_readonly("points_object", &Reconstruction::points_object,
                    "(F, 3, P) S_t, computed when the result was made")
      .def_readonly("summary", &Reconstruction::summary,
                    "dict: result.json of the tool (reconstruct) or the refinement summary")
      .def_readonly("dropped_points", &Reconstruction::dropped_points,
                    "points left out for too few observations (NaN in the arrays)")
      .def_readonly("dropped_frames", &Reconstruction::dropped_frames,
                    "frames left out for too few observations (NaN in the arrays)")
      .def("__repr__", [](const Reconstruction& r) {
        const py::array w = r.weights, b = r.basis, rot = r.rotations;
        return "<nrsfm.Reconstruction F=" + std::to_string(rot.shape(0)) +
               " M=" + std::to_string(rot.shape(1)) + " P=" + std::to_string(b.shape(2)) +
               " K=" + std::to_string(w.shape(1)) + ">";
      });

  py::class_<Tracks>(m, "Tracks", "Measurements: W (2FM, P), mask (FM, P), cameras M.")
      .def_readonly("W", &Tracks::W, "(2FM, P) float64, NaN = missing")
      .def_readonly("mask", &Tracks::mask, "(FM, P) bool, True = visible")
      .def_readonly("cameras", &Tracks::cameras, "M")
      .def_readonly("frame_ids", &Tracks::frame_ids,
                    "read: the list's index of each frame when an observation list too sparse "
                    "for a W over all its indices was renumbered to the frames it mentions; "
                    "else None")
      .def_readonly("point_ids", &Tracks::point_ids, "read: likewise for the points; else None")
      .def_readonly("confidence", &Tracks::confidence,
                    "read of a keypoint input: (FM, P) detector scores, NaN in frames with "
                    "no person; else None")
      .def_readonly("truth", &Tracks::truth,
                    "synth: a Reconstruction of the truth (reproject: the path of the "
                    "written file, scored in its object frame); else None")
      .def_readonly("P3_gt", &Tracks::P3_gt, "synth: (3F, P) camera 0's truth; else None")
      .def("__repr__", [](const Tracks& t) {
        const py::array w = t.W;
        return "<nrsfm.Tracks F=" + std::to_string(w.shape(0) / 2 / t.cameras) +
               " M=" + std::to_string(t.cameras) + " P=" + std::to_string(w.shape(1)) + ">";
      });

  m.attr("NrsfmWarning") = NrsfmWarning();
  m.def("reconstruct", &Reconstruct, Keep(ReconstructDoc()), py::arg("W"), py::arg("K"),
        py::arg("mask") = py::none(), py::arg("cameras") = 1,
        py::arg("progress") = py::none(), py::arg("observation_weights") = py::none());
  m.def("refine", &Refine, Keep(RefineDoc()), py::arg("W"), py::arg("model"),
        py::arg("mask") = py::none(), py::arg("cameras") = 1,
        py::arg("progress") = py::none(), py::arg("observation_weights") = py::none());
  m.def("read", &Read, Keep(ReadDoc()), py::arg("path"));
  m.def("evaluate", &Evaluate, Keep(EvaluateDoc()), py::arg("truth"), py::arg("result"));
  m.def("synth", &Synth, Keep(SynthDoc()));

  py::dict keywords;
  keywords["reconstruct"] = KeywordTable(ReconstructOptionsOf());
  keywords["refine"] = KeywordTable(RefineOptionsOf());
  keywords["read"] = KeywordTable(ReadOptionsOf());
  keywords["synth"] = KeywordTable(SynthOptionsOf());
  keywords["evaluate"] = KeywordTable(EvaluateOptionsOf());
  m.attr("OPTIONS") = keywords;
}
