#include "python/functions.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Eigen/Core>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/eval/metrics.h"
#include "core/io/ground_truth.h"
#include "core/io/mat_io.h"
#include "core/io/read_measurements.h"
#include "core/io/result_reader.h"
#include "core/io/result_writer.h"
#include "python/convert.h"
#include "python/keywords.h"
#include "solvers/refine/refine.h"
#include "tools/command_flags.h"
#include "tools/flag_table.h"
#include "tools/reconstruction_steps.h"
#include "tools/synth_steps.h"

namespace py = pybind11;

namespace nrsfm {
namespace python {

using tools::CommandFlags;

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
      throw py::type_error(
          "progress must be callable (iteration, cost, seconds) or None");
    }
  }

  void Configure(SolverOptions* solver) {
    solver->progress = [this](const IterationReport& report) {
      OnIteration(report);
    };
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
      if (!progress_.is_none())
        progress_(report.iteration, report.cost, report.seconds);
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
    type = new py::object(
        py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
            "nrsfm.NrsfmWarning",
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
  py::object error =
      py::module_::import("builtins").attr("ValueError")(message);
  error.attr("result") = result;
  PyErr_SetObject(PyExc_ValueError, error.ptr());
  throw py::error_already_set();
}

py::dict JsonToDict(const std::string& text) {
  return py::module_::import("json").attr("loads")(text);
}

// The options of a reconstruction or refinement of arrays from `flags` (the
// keywords and K set) and the measurements of W and mask they apply to, as
// the tool's steps check them (tools/reconstruction_steps.h).
Measurements ArrayTargets(py::handle w, py::handle mask, int cameras,
                          py::handle observation_weights, CommandFlags* flags,
                          tools::FlagTargets* targets,
                          py::handle intrinsics = py::none()) {
  flags->cameras = cameras;
  Check(tools::ApplyFlags(*flags, targets));
  Measurements measurements = MeasurementsOf(w, mask, cameras);
  if (!intrinsics.is_none()) {
    measurements.intrinsics = IntrinsicsOf(intrinsics, cameras);
    Check(measurements.Validate());
  }
  Check(tools::ArrayReconstructOptions(
      measurements, ObservationWeightsOf(observation_weights), flags, targets));
  return measurements;
}

// ---------------------------------------------------------------------------
// The functions.

Reconstruction Reconstruct(py::handle w, py::handle k, py::handle mask,
                           int cameras, py::object progress,
                           py::handle observation_weights,
                           py::handle intrinsics, const py::kwargs& kwargs) {
  CommandFlags flags;
  ApplyKeywords(ReconstructOptionsOf(), "reconstruct", kwargs, &flags);
  if (py::isinstance<py::str>(k)) {
    flags.K = k.cast<std::string>();
  } else {
    flags.K = std::to_string(IntegerFromPython(k, "K"));
  }
  tools::FlagTargets targets;
  const Measurements measurements = ArrayTargets(
      w, mask, cameras, observation_weights, &flags, &targets, intrinsics);

  Interruptible interruptible(std::move(progress));
  interruptible.Configure(&targets.reconstruct.solver);
  tools::ReconstructionRun run;
  Check(interruptible.Run([&] {
    return tools::RunReconstruction(targets, measurements, "", &run);
  }));

  const ReconstructionReport report =
      tools::MakeReport(flags, "", run, nullptr);
  Reconstruction result = FromModel(run.result.model);
  result.summary =
      JsonToDict(ReconstructionJson(measurements, run.result.model, report));
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
  if (run.uncertainty_requested && run.uncertainty_status.ok()) {
    const py::ssize_t f = measurements.num_frames, m = measurements.num_cameras,
                      p = measurements.num_points;
    py::array_t<double> points({f, m, p, py::ssize_t{3}, py::ssize_t{3}});
    py::array_t<double> rotations({f, m, py::ssize_t{3}, py::ssize_t{3}});
    double* out = points.mutable_data();
    for (const Eigen::Matrix3d& c : run.uncertainty.points) {
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) *out++ = c(i, j);
      }
    }
    out = rotations.mutable_data();
    for (const Eigen::Matrix3d& c : run.uncertainty.rotations) {
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) *out++ = c(i, j);
      }
    }
    result.points_covariance = points;
    result.rotations_covariance = rotations;
  }
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

Reconstruction Refine(py::handle w, py::handle model_object, py::handle mask,
                      int cameras, py::object progress,
                      py::handle observation_weights, py::handle intrinsics,
                      const py::kwargs& kwargs) {
  CommandFlags flags;
  ApplyKeywords(RefineOptionsOf(), "refine", kwargs, &flags);
  tools::FlagTargets targets;
  const Measurements measurements = ArrayTargets(
      w, mask, cameras, observation_weights, &flags, &targets, intrinsics);
  ReconstructOptions& options = targets.reconstruct;
  Model model = ModelFromPython(model_object, measurements);

  Interruptible interruptible(std::move(progress));
  interruptible.Configure(&options.solver);
  RefineSummary summary;
  Check(interruptible.Run([&] {
    return nrsfm::Refine(options.problem, options.solver, measurements, &model,
                         &summary);
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
  for (const auto& [name, weight] : options.problem.term_weights)
    weights[py::str(name)] = weight;
  s["term_weights"] = weights;
  py::dict used;
  const CommandFlags& f = flags;
  for (const Flag* flag : RefineOptionsOf().flags)
    used[py::str(flag->name())] = flag->get(f);
  s["options"] = used;
  s["observation_weights"] = options.problem.observation_weights.size() > 0;
  result.summary = s;
  if (!summary.usable) {
    ThrowUnusable(
        "the refinement did not give a usable solution (" + summary.message +
            "); the exception's .result holds the model given, unchanged",
        py::cast(result));
  }
  return result;
}

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
  tools::FlagTargets targets;
  Check(tools::ApplyFlags(flags, &targets));
  const InputOptions& input = targets.input;
  Measurements m;
  InputDetails details;
  const Status status = ReadMeasurements(path, input, &m, &details);
  // A folder is an input (OpenPose's) unless a file's format is asked for.
  const std::string extension =
      std::filesystem::path(path).extension().string();
  const bool folder_input =
      input.format == InputFormat::kOpenPose ||
      (input.format == InputFormat::kAuto && extension != ".mat");
  if (!status.ok()) ThrowFileError(path, status, folder_input);
  Tracks tracks = TracksOf(m);
  if (details.confidence.size() > 0) {
    Array confidence =
        NewArray({details.confidence.rows(), details.confidence.cols()});
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
      ThrowValueError(
          "synth: dataset 'reproject' needs output= (a .mat path): its truth "
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
  const std::vector<MatVariable> variables =
      tools::SyntheticVariables(sequence);
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
      for (Eigen::Index j = 0; j < variable.value.cols(); ++j)
        a(i, j) = variable.value(i, j);
    }
    tracks.P3_gt = p3;
  }
  return tracks;
}

// Shapes (F, 3, P) as a camera-frame GroundTruth.
std::vector<Eigen::Matrix3Xd> ShapesOf(py::handle object,
                                       const std::string& name) {
  const auto array = AsDoubleArray(object, name);
  if (array.ndim() != 3 || array.shape(1) != 3) {
    ThrowValueError(name + " has shape " + ShapeString(array) +
                    ", expected (F, 3, P)");
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
std::vector<Eigen::Matrix3Xd> CameraZeroOf(py::handle object,
                                           const std::string& name) {
  const auto array = AsDoubleArray(object, name);
  if (array.ndim() != 4 || array.shape(1) < 1 || array.shape(2) != 3) {
    ThrowValueError(name + " has shape " + ShapeString(array) +
                    ", expected (F, M, 3, P)");
  }
  py::object first =
      array[py::make_tuple(py::slice(py::none(), py::none(), py::none()), 0)];
  return ShapesOf(first, name + "[:, 0]");
}

// The truth or the estimate of evaluate: a path (as --truth / --result), an
// array (F, 3, P) of camera-frame shapes, or an object with points_camera
// (and, for the estimate, points_object and rotations: its object frame).
GroundTruth ShapesForEvaluation(py::handle object, bool is_truth,
                                const std::string& variable) {
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
    if (truth.is_none())
      ThrowValueError("truth: these Tracks have no truth (only synth's do)");
    return ShapesForEvaluation(truth, is_truth, variable);
  }
  if (py::hasattr(object, "points_camera") ||
      py::isinstance<py::dict>(object)) {
    py::object points_camera = Field(object, "points_camera");
    if (points_camera.is_none())
      ThrowValueError(name + " has no points_camera");
    shapes.points_in_camera =
        CameraZeroOf(points_camera, name + ".points_camera");
    shapes.source = "points_camera";
    py::object points_object = Field(object, "points_object");
    py::object rotations = Field(object, "rotations");
    if (!is_truth && !points_object.is_none() && !rotations.is_none()) {
      shapes.points_in_object =
          ShapesOf(points_object, name + ".points_object");
      const auto r = AsDoubleArray(rotations, name + ".rotations");
      if (r.ndim() != 4 ||
          r.shape(0) !=
              static_cast<py::ssize_t>(shapes.points_in_camera.size()) ||
          r.shape(1) < 1 || r.shape(2) != 3 || r.shape(3) != 3) {
        ThrowValueError(
            name + ".rotations has shape " + ShapeString(r) + ", expected (" +
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

py::dict Evaluate(py::handle truth_object, py::handle result_object,
                  const py::kwargs& kwargs) {
  CommandFlags flags;
  ApplyKeywords(EvaluateOptionsOf(), "evaluate", kwargs, &flags);
  const GroundTruth truth =
      ShapesForEvaluation(truth_object, true, flags.truth_var);
  const GroundTruth estimate = ShapesForEvaluation(result_object, false, "");
  ShapeErrors errors;
  Check(EvaluateShapes(truth, estimate, &errors));
  // The rank-K floor beside an object-frame e3D, K from a result's weights.
  int num_bases = 0;
  double floor = -1.0;
  if (errors.e3d_frame == EvaluationFrame::kObject &&
      py::hasattr(result_object, "weights")) {
    const py::array weights = py::array::ensure(result_object.attr("weights"));
    if (weights && weights.ndim() == 2 && weights.shape(1) >= 1) {
      num_bases = static_cast<int>(weights.shape(1));
      floor = ComputeRankFloorE3D(truth.points_in_object, num_bases);
    }
  }
  return JsonToDict(tools::EvaluationJson(errors, num_bases, floor));
}

}  // namespace python
}  // namespace nrsfm
