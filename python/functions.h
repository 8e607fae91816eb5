// The functions of the Python module `nrsfm` (python/nrsfm_module.cc binds
// them and holds their docstrings): reconstruct, refine, read, synth,
// track and evaluate, each running the nrsfm tool's steps (tools/) with its
// options as keywords and its messages as exceptions.
#ifndef NRSFM_PYTHON_FUNCTIONS_H_
#define NRSFM_PYTHON_FUNCTIONS_H_

#include <pybind11/pybind11.h>

#include "python/convert.h"

namespace nrsfm {
namespace python {

namespace py = pybind11;

// Measurements as arrays (read, synth).
struct Tracks {
  py::object W, mask;
  int cameras = 1;
  // read: the file's index of each frame and point when the reader
  // renumbered them (core/io/text_io.h, a sparse observation list); else None.
  py::object frame_ids = py::none();
  py::object point_ids = py::none();
  // read() of a keypoint input: the detector's score of each keypoint,
  // (FM, P), NaN in frames with no person; else None.
  py::object confidence = py::none();
  py::object truth = py::none();  // synth: a Reconstruction of the truth
  // synth: camera 0's truth, (3F, P) block layout
  py::object P3_gt = py::none();
  // track: (F, P, 2) every position from each point's start on (the
  // prediction where it is not visible; NaN before its start).
  py::object positions = py::none();
};

// nrsfm.NrsfmWarning, the category of the warnings about a result.
py::object NrsfmWarning();

Reconstruction Reconstruct(py::handle w, py::handle k, py::handle mask,
                           int cameras, py::object progress,
                           py::handle observation_weights,
                           py::handle intrinsics, const py::kwargs& kwargs);
Reconstruction Refine(py::handle w, py::handle model_object, py::handle mask,
                      int cameras, py::object progress,
                      py::handle observation_weights, py::handle intrinsics,
                      const py::kwargs& kwargs);
Tracks Read(py::handle path_object, const py::kwargs& kwargs);
Tracks Synth(const py::kwargs& kwargs);
Tracks Track(py::handle frames, py::handle queries, py::handle mask,
             const py::kwargs& kwargs);
py::dict Evaluate(py::handle truth_object, py::handle result_object,
                  const py::kwargs& kwargs);

}  // namespace python
}  // namespace nrsfm

#endif  // NRSFM_PYTHON_FUNCTIONS_H_
