// The Python module's conversions (python/nrsfm_module.cc): errors as Python
// exceptions, array-likes to Eigen and measurements and back, a model to and
// from a Reconstruction. Array conventions: the module's docstring
// (kConventions) and docs/python.md. Inputs are copied element by element by
// index (any dtype convertible to float64, any order or strides); outputs are
// new C-contiguous float64 arrays.
#ifndef NRSFM_PYTHON_CONVERT_H_
#define NRSFM_PYTHON_CONVERT_H_

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"

namespace nrsfm {
namespace python {

namespace py = pybind11;

// A Status error as ValueError with its message.
[[noreturn]] void ThrowValueError(const std::string& message);

// ValueError with the message of `status` when it is an error.
void Check(const Status& status);

// A failed read of `path`: an OSError subclass when the path cannot be
// opened as a file (missing, a directory unless `directory_allowed`, no
// permission), ValueError when the file's contents are at fault. The
// message is the tool's.
[[noreturn]] void ThrowFileError(const std::string& path, const Status& status,
                                 bool directory_allowed = false);

// A filesystem path from str or os.PathLike; TypeError naming `what`.
std::string PathOf(py::handle object, const char* what);

// Whether `object` is a str or os.PathLike.
bool IsPath(py::handle object);

// An integer argument: a Python int or numpy integer, not a bool; TypeError
// naming `name` otherwise, ValueError when it does not fit in 64 bits.
long long IntegerFromPython(py::handle value, const std::string& name);

using Array = py::array_t<double, py::array::c_style>;

// Any array-like as float64 (a copy when it is not already float64; any
// order or strides). ValueError naming `name` when it cannot be.
py::array_t<double, py::array::forcecast> AsDoubleArray(
    py::handle object, const std::string& name);

// "(2, 3)", "(4,)": an array's shape as Python prints it.
std::string ShapeString(const py::array& array);

// A 2-D array-like as an Eigen matrix, element (i, j) = array[i, j].
Eigen::MatrixXd ToMatrix(py::handle object, const std::string& name);

// An array of exactly `shape`, or ValueError naming it.
py::array_t<double, py::array::forcecast> WithShape(
    py::handle object, const std::string& name,
    const std::vector<py::ssize_t>& shape);

// A new C-contiguous float64 array of `shape`.
Array NewArray(const std::vector<py::ssize_t>& shape);

// Measurements from W (2FM, P; NaN = missing) and an optional mask (None,
// (FM, P) or (2FM, P), nonzero = visible); ValueError with the tool's
// message (tools::MeasurementsFromArrays).
Measurements MeasurementsOf(py::handle w_object, py::handle mask_object,
                            int cameras);

// The intrinsics argument: (M, 4) rows fx, fy, cx, cy per camera, or (4,)
// for one camera, as Measurements::intrinsics (4 × M); ValueError naming it
// when its shape does not fit.
Eigen::Matrix4Xd IntrinsicsOf(py::handle object, int cameras);

// W (2FM, P) with NaN at the missing entries.
py::array WArray(const Measurements& m);

// Observation weights (FM, P) as given (None = empty); scaled by
// tools::ArrayReconstructOptions.
Eigen::ArrayXXd ObservationWeightsOf(py::handle object);

// The visibility mask (FM, P), bool.
py::array MaskArray(const Measurements& m);

// A reconstruction (or a model given to refine, or a synthetic truth): the
// model's blocks as arrays, the shapes they give, and what the solve said.
struct Reconstruction {
  py::object rotations, translations, scales, weights, basis, rig_rotations,
      rig_scales;
  py::object points_camera, points_object;
  py::dict summary;
  py::list dropped_points, dropped_frames;
  // uncertainty=True: (F, M, P, 3, 3) and (F, M, 3, 3); None otherwise.
  py::object points_covariance = py::none(), rotations_covariance = py::none();
};

// The arrays of `model` (summary and dropped lists left empty).
Reconstruction FromModel(const Model& model);

// Attribute `name` of `object`, or key `name` of a mapping; None if absent.
py::object Field(py::handle object, const char* name);

// A model for refine() from a Reconstruction or a mapping with its fields,
// sized by `m`; ValueError naming the field that does not fit. With the
// intrinsics of every camera in `m` it is a pinhole model (docs/camera.md):
// translations (F, M, 3), t_z last; else weak perspective, (F, M, 2).
Model ModelFromPython(py::handle object, const Measurements& m);

}  // namespace python
}  // namespace nrsfm

#endif  // NRSFM_PYTHON_CONVERT_H_
