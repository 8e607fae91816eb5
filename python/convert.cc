#include "python/convert.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Eigen/Core>
#include <Eigen/LU>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/io/read_measurements.h"
#include "core/math/rotation.h"
#include "tools/command_flags.h"
#include "tools/flag_table.h"
#include "tools/reconstruction_steps.h"

namespace py = pybind11;

namespace nrsfm {
namespace python {

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
                                 bool directory_allowed) {
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
    throw py::type_error(
        std::string(what) + " must be a path (str or os.PathLike), got " +
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

// An integer argument: a Python int or numpy integer, not a bool.
long long IntegerFromPython(py::handle value, const std::string& name) {
  if (py::isinstance<py::bool_>(value) || !PyIndex_Check(value.ptr())) {
    throw py::type_error(
        name + " must be an int, got " +
        std::string(py::str(py::type::of(value).attr("__name__"))));
  }
  py::int_ index = py::reinterpret_steal<py::int_>(PyNumber_Index(value.ptr()));
  int overflow = 0;
  const long long result = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
  if (overflow != 0) throw py::value_error(name + " is out of range");
  return result;
}

// ---------------------------------------------------------------------------
// Arrays.

using Array = py::array_t<double, py::array::c_style>;

// Any array-like as float64 (a copy when it is not already float64; any
// order or strides). ValueError naming `name` when it cannot be.
py::array_t<double, py::array::forcecast> AsDoubleArray(
    py::handle object, const std::string& name) {
  if (object.is_none()) ThrowValueError(name + " is None");
  py::array_t<double, py::array::forcecast> array;
  try {
    array = py::array_t<double, py::array::forcecast>::ensure(object);
  } catch (py::error_already_set&) {
    array = py::array_t<double, py::array::forcecast>();
  }
  if (!array) {
    PyErr_Clear();
    ThrowValueError(
        name + " must be an array of numbers (convertible to float64), got " +
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
    ThrowValueError(name + " must be a 2-D array, got shape " +
                    ShapeString(array));
  }
  const auto a = array.unchecked<2>();
  Eigen::MatrixXd m(a.shape(0), a.shape(1));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    for (py::ssize_t j = 0; j < a.shape(1); ++j) m(i, j) = a(i, j);
  }
  return m;
}

// An array of exactly `shape`, or ValueError naming it.
py::array_t<double, py::array::forcecast> WithShape(
    py::handle object, const std::string& name,
    const std::vector<py::ssize_t>& shape) {
  const auto array = AsDoubleArray(object, name);
  bool same = array.ndim() == static_cast<py::ssize_t>(shape.size());
  for (std::size_t i = 0; same && i < shape.size(); ++i)
    same = array.shape(i) == shape[i];
  if (!same) {
    std::string expected = "(";
    for (std::size_t i = 0; i < shape.size(); ++i) {
      expected += (i ? ", " : "") + std::to_string(shape[i]);
    }
    expected += shape.size() == 1 ? ",)" : ")";
    ThrowValueError(name + " has shape " + ShapeString(array) + ", expected " +
                    expected);
  }
  return array;
}

Array NewArray(const std::vector<py::ssize_t>& shape) { return Array(shape); }

Eigen::Matrix4Xd IntrinsicsOf(py::handle object, int cameras) {
  const auto array = AsDoubleArray(object, "intrinsics");
  const bool one = array.ndim() == 1 && array.shape(0) == 4 && cameras == 1;
  if (!one && !(array.ndim() == 2 && array.shape(0) == cameras &&
                array.shape(1) == 4)) {
    ThrowValueError(
        "intrinsics has shape " + ShapeString(array) + ", expected (" +
        std::to_string(cameras) +
        ", 4): fx, fy, cx, cy of each of the M = " + std::to_string(cameras) +
        " cameras" + (cameras == 1 ? " (or (4,))" : ""));
  }
  Eigen::Matrix4Xd intrinsics(4, cameras);
  for (int c = 0; c < cameras; ++c) {
    for (int i = 0; i < 4; ++i) {
      intrinsics(i, c) =
          one ? array.unchecked<1>()(i) : array.unchecked<2>()(c, i);
    }
  }
  return intrinsics;
}

// Measurements from W (2FM × P) and an optional mask, named "W" and "mask"
// in the messages.
Measurements MeasurementsOf(py::handle w_object, py::handle mask_object,
                            int cameras) {
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

Reconstruction FromModel(const Model& model) {
  const int f = model.num_frames, m = model.num_cameras, p = model.num_points,
            k = model.num_bases;
  Reconstruction r;
  const bool perspective = model.camera == CameraModel::kPerspective;
  const int translation_size = perspective ? 3 : 2;
  Array rotations = NewArray({f, m, 3, 3}),
        translations = NewArray({f, m, translation_size}),
        scales = NewArray({f, m}), weights = NewArray({f, k}),
        basis = NewArray({k, 3, p}), rig_rotations = NewArray({m - 1, 3, 3}),
        rig_scales = NewArray({m - 1}), points_camera = NewArray({f, m, 3, p}),
        points_object = NewArray({f, 3, p});
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
      for (int i = 0; i < 2; ++i)
        tra(t, c, i) = model.translations(i, model.View(t, c));
      if (perspective) tra(t, c, 2) = model.depths(model.View(t, c));
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
    ThrowValueError(
        "model must have rotations, translations, weights and basis "
        "(attributes or keys)");
  }
  const auto weights_array = AsDoubleArray(weights_object, "model.weights");
  if (weights_array.ndim() != 2 || weights_array.shape(0) != f ||
      weights_array.shape(1) < 1) {
    ThrowValueError("model.weights has shape " + ShapeString(weights_array) +
                    ", expected (" + std::to_string(f) +
                    ", K) for the F = " + std::to_string(f) + " frames of W");
  }
  const int k = static_cast<int>(weights_array.shape(1));
  Model model;
  model.Resize(f, cams, p, k);
  auto required = [&](const char* name) {
    py::object value = Field(object, name);
    if (value.is_none()) ThrowValueError(std::string("model has no ") + name);
    return value;
  };
  const auto rotations =
      WithShape(required("rotations"), "model.rotations", {f, cams, 3, 3});
  const bool perspective = m.intrinsics.cols() == cams;
  if (perspective) {
    model.camera = CameraModel::kPerspective;
    model.intrinsics = m.intrinsics;
  }
  const auto given =
      AsDoubleArray(required("translations"), "model.translations");
  if (!perspective && given.ndim() == 3 && given.shape(2) == 3) {
    ThrowValueError(
        "model.translations has a depth t_z (shape (F, M, 3)): a perspective "
        "model, which refine() takes with intrinsics=[fx, fy, cx, cy]");
  }
  const auto translations =
      WithShape(given, "model.translations", {f, cams, perspective ? 3 : 2});
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
        ThrowValueError(where +
                        " is not finite (a reconstruction that left frames out "
                        "holds NaN there; refine needs a finite model)");
      }
      if ((r * r.transpose() - Eigen::Matrix3d::Identity())
                  .cwiseAbs()
                  .maxCoeff() > 1e-6 ||
          r.determinant() < 0.0) {
        ThrowValueError(
            where +
            " is not a rotation matrix (R R^T = I and det R = +1 to 1e-6)");
      }
      model.SetRotation(t, c, r);
      for (int i = 0; i < 2; ++i)
        model.translations(i, model.View(t, c)) = tra(t, c, i);
      if (perspective) model.depths(model.View(t, c)) = tra(t, c, 2);
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
    const auto r =
        WithShape(rig_rotations, "model.rig_rotations", {cams - 1, 3, 3});
    auto a = r.unchecked<3>();
    for (int c = 0; c + 1 < cams; ++c) {
      Eigen::Matrix3d m3;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) m3(i, j) = a(c, i, j);
      }
      if (!m3.allFinite() ||
          (m3 * m3.transpose() - Eigen::Matrix3d::Identity())
                  .cwiseAbs()
                  .maxCoeff() > 1e-6 ||
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

}  // namespace python
}  // namespace nrsfm
