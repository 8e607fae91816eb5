// The Python module `nrsfm` (pybind11): reconstruct, refine, read, evaluate
// and synth on numpy arrays, with the nrsfm tool's options and messages
// (the keywords are the tool's flags by their role, tools/flag_table.h:
// NRSFM_COMMAND_FLAGS and the extra-term table).
//
// Conventions (docs/guide.md, "Python"):
//   W        (2FM, P), rows u, v of frame t, camera c at 2(tM + c) and
//            2(tM + c) + 1 (core/model/measurements.h); NaN = missing.
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

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "python/convert.h"
#include "python/functions.h"
#include "python/keywords.h"
#include "solvers/refine/refine.h"
#include "tools/command_flags.h"
#include "tools/flag_table.h"

namespace py = pybind11;

namespace nrsfm {
namespace python {
namespace {

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
With camera='perspective' (docs/camera.md) translations are (F, M, 3), the
depth t_z last, points_camera = R_tc S_t + T_tc and W is its pinhole image.
Inputs may be any array-like convertible to float64 in any memory order;
they are copied. Outputs are new C-contiguous float64 arrays.
)";

std::string ReconstructDoc() {
  return "reconstruct(W, K, mask=None, cameras=1, progress=None, "
         "observation_weights=None,\n"
         "            intrinsics=None, **options) -> Reconstruction\n"
         "\n"
         "The closed-form start and its Ceres refinement, as `nrsfm "
         "reconstruct`\n"
         "(README.md, docs/priors.md). K is an int >= 1 or 'auto'. progress, "
         "if given,\n"
         "is called as progress(iteration, cost, seconds) once per "
         "Levenberg-Marquardt\n"
         "iteration; an exception it raises (and Ctrl-C) stops the solve and "
         "is raised.\n"
         "The solve runs without the GIL.\n"
         "observation_weights, if given, (FM, P): relative weights of the "
         "observations'\n"
         "residuals (e.g. read()'s confidence of a keypoint input, as the "
         "tool's\n"
         "--confidence_weights), scaled to average 1 over the visible "
         "observations.\n"
         "intrinsics, if given, (M, 4) or (4,) for one camera: fx, fy, cx, cy "
         "of each\n"
         "camera in the units of W, for camera='perspective' (docs/camera.md); "
         "the\n"
         "translations are then (F, M, 3) with the depth t_z last.\n"
         "\n"
         "Returns a Reconstruction: the arrays below, summary (the dict nrsfm "
         "writes as\n"
         "result.json, plus K_selection with K = 'auto'), dropped_points and\n"
         "dropped_frames (left out for too few observations: NaN in the "
         "arrays).\n"
         "Warnings (points left out, little rotation) are issued as "
         "NrsfmWarning.\n"
         "Raises ValueError with the tool's message on bad input; when the "
         "refinement\n"
         "is not usable, ValueError whose .result holds the start.\n"
         "\n"
         "Keyword options (the tool's flags, same names and defaults):\n" +
         KeywordDoc(ReconstructOptionsOf()) + kConventions;
}

std::string RefineDoc() {
  return "refine(W, model, mask=None, cameras=1, progress=None, "
         "observation_weights=None,\n"
         "       intrinsics=None, **options) -> Reconstruction\n"
         "\n"
         "Levenberg-Marquardt refinement of a model of your own (the library's "
         "Refine(),\n"
         "solvers/refine/refine.h) against W, with exactly the term weights "
         "given. "
         "model is a\n"
         "Reconstruction, any object with the attributes, or a dict: "
         "rotations,\n"
         "translations, weights, basis required; scales, rig_rotations, "
         "rig_scales\n"
         "optional (1, identity, 1); shapes as below. The model given is not "
         "changed.\n"
         "With intrinsics ((M, 4) or (4,), fx, fy, cx, cy) the model is a "
         "pinhole one:\n"
         "translations (F, M, 3), t_z last; its depths and the basis of the "
         "most observed\n"
         "point are held (the gauges, docs/camera.md).\n"
         "progress, Ctrl-C and observation_weights as for reconstruct. "
         "summary: usable,\n"
         "converged, stopped,\n"
         "message, costs, reprojection RMS, iterations, linear solver, "
         "seconds.\n"
         "Raises ValueError on bad input, and whose .result holds the model "
         "given when\n"
         "the refinement is not usable.\n"
         "\n"
         "Keyword options:\n" +
         KeywordDoc(RefineOptionsOf()) + kConventions;
}

std::string ReadDoc() {
  return "read(path, **options) -> Tracks\n"
         "\n"
         "Reads measurements as `nrsfm reconstruct --input` does: .mat "
         "v4/v5/v7.3 (W,\n"
         "P3_gt or X), text/CSV W, observation list (.obs/.list), COCO "
         "keypoint results\n"
         "(.json) or a folder of OpenPose .json frames (pixels, v down). "
         "Returns Tracks\n"
         "with W (2FM, P, NaN = missing), mask (FM, P, bool), cameras (M) and, "
         "for\n"
         "keypoints, confidence (FM, P; the detector's scores, NaN in frames "
         "with no\n"
         "person); what the file's frames lack (no person) is issued as "
         "NrsfmWarning.\n"
         "Raises OSError\n"
         "(FileNotFoundError, IsADirectoryError, PermissionError) when the "
         "file cannot be\n"
         "opened, ValueError when its contents are at fault.\n"
         "\n"
         "Keyword options:\n" +
         KeywordDoc(ReadOptionsOf());
}

std::string SynthDoc() {
  return "synth(**options) -> Tracks\n"
         "\n"
         "A synthetic sequence, as `nrsfm synth` (core/synthetic/synthetic.h): "
         "Tracks "
         "with W, mask,\n"
         "cameras, truth (a Reconstruction of the generating model) and P3_gt "
         "(camera\n"
         "0's truth with translations, (3F, P), rows x of every frame, then y, "
         "then z).\n"
         "With output='PATH.mat' the same .mat file as the tool is written "
         "too.\n"
         "\n"
         "Keyword options:\n" +
         KeywordDoc(SynthOptionsOf());
}

std::string TrackDoc() {
  return "track(frames, queries=None, mask=None, **options) -> Tracks\n"
         "\n"
         "Point tracks from frames, as `nrsfm track` (docs/tracking.md): "
         "frames is a\n"
         "folder of images, a video file, or an (F, H, W) or (F, H, W, 3) "
         "uint8 array\n"
         "(BGR); queries None (the tracker chooses points in the first "
         "frame), a CSV\n"
         "path (point,frame,x,y) or an (N, 4) array of point, frame, x, y "
         "(pixels,\n"
         "x right, y down; frame a frame number); mask None or frames of "
         "the object\n"
         "mask (nonzero = object). Returns Tracks with W (2F, P; NaN where "
         "not\n"
         "visible), mask (F, P, visible), positions (F, P, 2: the "
         "prediction where\n"
         "not visible, NaN before a point's start), frame_ids (the frame "
         "numbers) and\n"
         "point_ids; reconstruct(t.W, K, mask=t.mask) takes them. Raises "
         "ValueError\n"
         "(or OSError for a path that cannot be opened) with the tool's "
         "message.\n"
         "\n"
         "Keyword options:\n" +
         KeywordDoc(TrackOptionsOf());
}

std::string EvaluateDoc() {
  return "evaluate(truth, result, **options) -> dict\n"
         "\n"
         "The metrics of `nrsfm evaluate` (core/eval/metrics.h, "
         "docs/metrics.md), "
         "the same\n"
         "dict as its JSON line: e3d, e3d_camera, frob_zsign, error3d_pct, "
         "zerror_pct,\n"
         "rotation_error (when both have rotations), e3d_frame, F, P, and\n"
         "unscored_frames / unscored_points when the result holds NaN there.\n"
         "truth: a path as --truth (.mat with S + Rs, P3_gt or X; a result "
         "directory),\n"
         "an array (F, 3, P) of camera-frame shapes, an object with "
         "points_camera\n"
         "(camera 0), or the Tracks of synth (their truth). result: a result "
         "directory or points_camera.csv, an array\n"
         "(F, 3, P), or a Reconstruction (camera 0 and its object frame, so a "
         "truth\n"
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
  m.doc() = Keep(std::string("nrsfm: non-rigid structure from motion "
                             "(docs/guide.md, \"Python\").\n\n"
                             "reconstruct, refine, read, evaluate and synth, "
                             "with the nrsfm tool's options\n"
                             "as keywords (same names and defaults; OPTIONS "
                             "lists them) and its messages.\n") +
                 kConventions);
  m.attr("__version__") = NRSFM_VERSION;

  py::class_<Reconstruction>(
      m, "Reconstruction",
      "A model as arrays (see the module's array conventions), the "
      "shapes it gives, and the summary of the solve.")
      .def_readonly("rotations", &Reconstruction::rotations,
                    "(F, M, 3, 3) R_tc")
      .def_readonly("translations", &Reconstruction::translations,
                    "(F, M, 2) T_tc")
      .def_readonly("scales", &Reconstruction::scales, "(F, M) s_tc")
      .def_readonly("weights", &Reconstruction::weights, "(F, K) l_tk")
      .def_readonly("basis", &Reconstruction::basis, "(K, 3, P) S_k")
      .def_readonly("rig_rotations", &Reconstruction::rig_rotations,
                    "(M - 1, 3, 3)")
      .def_readonly("rig_scales", &Reconstruction::rig_scales, "(M - 1,)")
      .def_readonly("points_camera", &Reconstruction::points_camera,
                    "(F, M, 3, P) X_tc = s_tc R_tc S_t, computed when the "
                    "result was made")
      .def_readonly("points_object", &Reconstruction::points_object,
                    "(F, 3, P) S_t, computed when the result was made")
      .def_readonly("summary", &Reconstruction::summary,
                    "dict: result.json of the tool (reconstruct) or the "
                    "refinement summary")
      .def_readonly(
          "dropped_points", &Reconstruction::dropped_points,
          "points left out for too few observations (NaN in the arrays)")
      .def_readonly(
          "dropped_frames", &Reconstruction::dropped_frames,
          "frames left out for too few observations (NaN in the arrays)")
      .def_readonly("points_covariance", &Reconstruction::points_covariance,
                    "uncertainty=True: (F, M, P, 3, 3) covariance of each "
                    "centred point of points_camera (docs/uncertainty.md); "
                    "else None")
      .def_readonly("rotations_covariance",
                    &Reconstruction::rotations_covariance,
                    "uncertainty=True: (F, M, 3, 3) covariance of each "
                    "rotation's body-frame perturbation, rad^2; else None")
      .def("__repr__", [](const Reconstruction& r) {
        const py::array w = r.weights, b = r.basis, rot = r.rotations;
        return "<nrsfm.Reconstruction F=" + std::to_string(rot.shape(0)) +
               " M=" + std::to_string(rot.shape(1)) +
               " P=" + std::to_string(b.shape(2)) +
               " K=" + std::to_string(w.shape(1)) + ">";
      });

  py::class_<Tracks>(m, "Tracks",
                     "Measurements: W (2FM, P), mask (FM, P), cameras M.")
      .def_readonly("W", &Tracks::W, "(2FM, P) float64, NaN = missing")
      .def_readonly("mask", &Tracks::mask, "(FM, P) bool, True = visible")
      .def_readonly("cameras", &Tracks::cameras, "M")
      .def_readonly("frame_ids", &Tracks::frame_ids,
                    "read: the list's index of each frame when an observation "
                    "list too sparse "
                    "for a W over all its indices was renumbered to the frames "
                    "it mentions; track: the frame numbers; "
                    "else None")
      .def_readonly("point_ids", &Tracks::point_ids,
                    "read: likewise for the points; track: the point ids; "
                    "else None")
      .def_readonly("confidence", &Tracks::confidence,
                    "read of a keypoint input: (FM, P) detector scores, NaN in "
                    "frames with "
                    "no person; else None")
      .def_readonly(
          "truth", &Tracks::truth,
          "synth: a Reconstruction of the truth (reproject: the path of the "
          "written file, scored in its object frame); else None")
      .def_readonly("P3_gt", &Tracks::P3_gt,
                    "synth: (3F, P) camera 0's truth; else None")
      .def_readonly("positions", &Tracks::positions,
                    "track: (F, P, 2) every position from each point's "
                    "start on (the prediction where not visible); else None")
      .def("__repr__", [](const Tracks& t) {
        const py::array w = t.W;
        return "<nrsfm.Tracks F=" + std::to_string(w.shape(0) / 2 / t.cameras) +
               " M=" + std::to_string(t.cameras) +
               " P=" + std::to_string(w.shape(1)) + ">";
      });

  m.attr("NrsfmWarning") = NrsfmWarning();
  m.def("reconstruct", &Reconstruct, Keep(ReconstructDoc()), py::arg("W"),
        py::arg("K"), py::arg("mask") = py::none(), py::arg("cameras") = 1,
        py::arg("progress") = py::none(),
        py::arg("observation_weights") = py::none(),
        py::arg("intrinsics") = py::none());
  m.def("refine", &Refine, Keep(RefineDoc()), py::arg("W"), py::arg("model"),
        py::arg("mask") = py::none(), py::arg("cameras") = 1,
        py::arg("progress") = py::none(),
        py::arg("observation_weights") = py::none(),
        py::arg("intrinsics") = py::none());
  m.def("read", &Read, Keep(ReadDoc()), py::arg("path"));
  m.def("evaluate", &Evaluate, Keep(EvaluateDoc()), py::arg("truth"),
        py::arg("result"));
  m.def("synth", &Synth, Keep(SynthDoc()));
  m.def("track", &Track, Keep(TrackDoc()), py::arg("frames"),
        py::arg("queries") = py::none(), py::arg("mask") = py::none());

  py::dict keywords;
  keywords["reconstruct"] = KeywordTable(ReconstructOptionsOf());
  keywords["refine"] = KeywordTable(RefineOptionsOf());
  keywords["read"] = KeywordTable(ReadOptionsOf());
  keywords["synth"] = KeywordTable(SynthOptionsOf());
  keywords["evaluate"] = KeywordTable(EvaluateOptionsOf());
  keywords["track"] = KeywordTable(TrackOptionsOf());
  m.attr("OPTIONS") = keywords;
}
