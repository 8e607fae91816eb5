#include "tools/commands.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <ceres/version.h>
#include <nlohmann/json.hpp>

#include "core/ground_truth.h"
#include "core/mat_io.h"
#include "core/metrics.h"
#include "core/read_measurements.h"
#include "core/result_reader.h"
#include "core/result_writer.h"
#include "core/synthetic.h"
#include "problems/extra_terms.h"
#include "solvers/reconstruct.h"
#include "solvers/select_num_bases.h"

namespace nrsfm {
namespace tools {
namespace {

#define NRSFM_STRINGIZE2(x) #x
#define NRSFM_STRINGIZE(x) NRSFM_STRINGIZE2(x)
constexpr char kVersion[] =
    NRSFM_VERSION " (Ceres " CERES_VERSION_STRING ", Eigen " NRSFM_STRINGIZE(
        EIGEN_WORLD_VERSION) "." NRSFM_STRINGIZE(EIGEN_MAJOR_VERSION) "." NRSFM_STRINGIZE(EIGEN_MINOR_VERSION) ")";

// Parses a whole string as an integer; false on anything else.
bool ParseInt(const std::string& s, int* value) {
  if (s.empty()) return false;
  size_t used = 0;
  try {
    const long v = std::stol(s, &used);
    if (used != s.size() || v < -1000000000L || v > 1000000000L) return false;
    *value = static_cast<int>(v);
  } catch (...) {
    return false;
  }
  return true;
}

Status CheckFinite(const char* flag, double value) {
  if (!std::isfinite(value)) {
    return Status::Error(std::string("--") + flag + " must be a finite number");
  }
  return Status::OK();
}

// Ground truth from a .mat file or a result directory (points_camera.csv).
Status ReadTruth(const std::string& path, const std::string& variable,
                 GroundTruth* truth) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    return ReadPointsCameraCsv(path, /*camera=*/0, truth);
  }
  return ReadGroundTruth(path, variable, truth);
}

std::string FormatDouble(double value) {
  std::ostringstream s;
  s << std::setprecision(6) << value;
  return s.str();
}

Status BuildReconstructOptions(const CommandFlags& flags,
                               ReconstructOptions* options) {
  NRSFM_RETURN_IF_ERROR(ParseStartMethod(flags.init, &options->start.method)
                            .WithContext("--init"));
  NRSFM_RETURN_IF_ERROR(ParseRobustLoss(flags.robust, &options->problem.robust_loss)
                            .WithContext("--robust"));
  NRSFM_RETURN_IF_ERROR(
      ParseLinearSolver(flags.linear_solver, &options->solver.linear_solver)
          .WithContext("--linear_solver"));
  NRSFM_RETURN_IF_ERROR(ParsePriorMode(flags.priors, &options->priors)
                            .WithContext("--priors"));
  // One flag per extra term (problems/extra_terms.h).
  const std::vector<ExtraTerm>& terms = ExtraTerms();
  for (std::size_t i = 0; i < terms.size(); ++i) {
    const std::string flag = std::string("--") + terms[i].flag;
    const double weight = flags.term_weights[i];
    if (!(std::isfinite(weight) && weight >= 0.0)) {
      return Status::Error(flag + " must be a finite number >= 0, got " +
                           FormatDouble(weight));
    }
    if (weight > 0.0 && flags.cameras != 0 && flags.cameras < terms[i].min_cameras) {
      return Status::Error(flag + " needs synchronised cameras: --cameras must be >= " +
                           std::to_string(terms[i].min_cameras) + ", got " +
                           std::to_string(flags.cameras));
    }
    if (weight > 0.0) options->problem.term_weights[terms[i].name] = weight;
  }
  // A weight given on the command line is a manual choice of the terms.
  if (!options->problem.term_weights.empty()) options->priors = PriorMode::kManual;
  options->start.seed = flags.seed;
  options->problem.robust_scale = flags.robust_scale;
  options->solver.max_iterations = flags.max_iterations;
  options->solver.num_threads = flags.threads;
  return options->Check();
}

// The flags a reconstruction used, for result.json.
std::vector<std::pair<std::string, std::string>> OptionList(
    const CommandFlags& flags, int num_bases) {
  std::vector<std::pair<std::string, std::string>> list = {
      {"K", std::to_string(num_bases)},
      {"K_flag", flags.K},
      {"var", flags.var},
      {"mask_var", flags.mask_var},
      {"format", flags.format},
      {"cameras", std::to_string(flags.cameras)},
      {"init", flags.init},
      {"priors", flags.priors}};
  for (std::size_t i = 0; i < ExtraTerms().size(); ++i) {
    list.emplace_back(ExtraTerms()[i].flag, FormatDouble(flags.term_weights[i]));
  }
  list.insert(list.end(), {{"robust", flags.robust},
                           {"robust_scale", FormatDouble(flags.robust_scale)},
                           {"max_iterations", std::to_string(flags.max_iterations)},
                           {"threads", std::to_string(flags.threads)},
                           {"linear_solver", flags.linear_solver},
                           {"seed", std::to_string(flags.seed)}});
  return list;
}

}  // namespace

const char* VersionString() { return kVersion; }

// The metrics of `errors` as written to result.json and printed by
// `evaluate` (rotation_error only when it was computed).
std::vector<std::pair<std::string, double>> MetricList(const ShapeErrors& errors) {
  std::vector<std::pair<std::string, double>> list = {
      {"e3d", errors.e3d},
      {"e3d_camera", errors.e3d_camera},
      {"frob_zsign", errors.frob_zsign},
      {"error3d_pct", errors.error3d_pct},
      {"zerror_pct", errors.zerror_pct}};
  if (!std::isnan(errors.rotation_error)) {
    list.emplace_back("rotation_error", errors.rotation_error);
  }
  return list;
}

Status RunReconstruct(const CommandFlags& flags, std::ostream& out,
                      std::ostream& progress) {
  if (flags.input.empty()) return Status::Error("--input is required");
  if (flags.output.empty()) return Status::Error("--output is required");
  if (flags.K.empty()) return Status::Error("--K is required (an integer >= 1 or 'auto')");
  const bool auto_k = flags.K == "auto";
  int num_bases = 0;
  if (!auto_k && (!ParseInt(flags.K, &num_bases) || num_bases < 1)) {
    return Status::Error("--K must be an integer >= 1 or 'auto', got '" + flags.K + "'");
  }
  if (flags.cameras < 0) {
    return Status::Error("--cameras must be >= 1 (or 0: from the file), got " +
                         std::to_string(flags.cameras));
  }
  ReconstructOptions options;
  NRSFM_RETURN_IF_ERROR(BuildReconstructOptions(flags, &options));

  // Refuse an output that cannot be written before spending time solving.
  if (!flags.overwrite) {
    std::error_code ec;
    if (std::filesystem::exists(flags.output, ec) &&
        !(std::filesystem::is_directory(flags.output, ec) &&
          std::filesystem::is_empty(flags.output, ec))) {
      return Status::Error("output '" + flags.output +
                           "' exists and is not an empty directory (use --overwrite "
                           "to replace an earlier result)");
    }
  }

  InputOptions input_options;
  input_options.variable = flags.var;
  input_options.mask_variable = flags.mask_var;
  input_options.num_cameras = flags.cameras;
  input_options.format = flags.format;
  Measurements measurements;
  NRSFM_RETURN_IF_ERROR(ReadMeasurements(flags.input, input_options, &measurements));
  for (std::size_t i = 0; i < ExtraTerms().size(); ++i) {
    if (flags.term_weights[i] > 0.0 &&
        measurements.num_cameras < ExtraTerms()[i].min_cameras) {
      return Status::Error(std::string("--") + ExtraTerms()[i].flag +
                           " needs synchronised cameras: M must be >= " +
                           std::to_string(ExtraTerms()[i].min_cameras) + ", but " +
                           flags.input + " has M = " +
                           std::to_string(measurements.num_cameras));
    }
  }

  GroundTruth truth;
  if (!flags.truth.empty()) {
    NRSFM_RETURN_IF_ERROR(ReadTruth(flags.truth, flags.truth_var, &truth));
    if (truth.NumFrames() != measurements.num_frames ||
        truth.NumPoints() != measurements.num_points) {
      return Status::Error("--truth '" + flags.truth + "' has F = " +
                           std::to_string(truth.NumFrames()) + ", P = " +
                           std::to_string(truth.NumPoints()) + " but the input has F = " +
                           std::to_string(measurements.num_frames) + ", P = " +
                           std::to_string(measurements.num_points));
    }
  }

  out << "input: " << flags.input << "  F = " << measurements.num_frames
      << ", M = " << measurements.num_cameras << ", P = " << measurements.num_points
      << ", visible " << measurements.NumVisible() << " of "
      << measurements.NumViews() * measurements.num_points << "\n";

  if (!flags.quiet) {
    options.solver.progress = [&progress](const IterationReport& report) {
      progress << "  iteration " << std::setw(4) << report.iteration << "  cost "
               << std::setprecision(6) << std::scientific << report.cost
               << std::defaultfloat << "  " << std::fixed << std::setprecision(2)
               << report.seconds << " s" << std::defaultfloat << "\n";
    };
  }

  ReconstructResult result;
  if (auto_k) {
    SelectNumBasesOptions select_options;
    select_options.max_num_bases = flags.K_max;
    select_options.threshold = flags.K_threshold;
    SelectNumBasesResult selection;
    NRSFM_RETURN_IF_ERROR(
        SelectNumBases(options, select_options, measurements, &selection)
            .WithContext("--K auto"));
    out << "K selection (noise estimate " << std::setprecision(4)
        << selection.noise_stddev << " per coordinate):\n";
    out << "   K   reprojection RMS   expected noise RMS   time [s]\n";
    for (const auto& c : selection.curve) {
      out << std::setw(4) << c.num_bases << "   ";
      if (c.ok) {
        out << std::setw(16) << std::setprecision(6) << c.reprojection_rms << "   "
            << std::setw(18) << c.expected_rms << "   " << std::setw(8)
            << std::setprecision(3) << c.seconds
            << (c.num_bases == selection.num_bases ? "   <- chosen" : "") << "\n";
      } else {
        out << "failed: " << c.message << "\n";
      }
    }
    num_bases = selection.num_bases;
    result = std::move(selection.reconstruction);
  } else {
    options.start.num_bases = num_bases;
    NRSFM_RETURN_IF_ERROR(
        Reconstruct(options, measurements, &result).WithContext(flags.input));
  }

  ReconstructionReport report;
  report.input = flags.input;
  report.options = OptionList(flags, num_bases);
  report.start_used = StartMethodName(result.start.method);
  report.start_reprojection_rms = result.start.reprojection_rms;
  report.stages.push_back({"initialize", 0.0, 0.0, 0, result.start.seconds});
  report.stages.push_back({"refine", result.refine.initial_cost,
                           result.refine.final_cost, result.refine.iterations,
                           result.refine.seconds});
  report.reprojection_rms = result.refine.usable ? result.refine.reprojection_rms
                                                 : result.start.reprojection_rms;
  report.solution_usable = result.refine.usable;
  report.warnings = result.start.warnings;
  report.warnings.insert(report.warnings.end(), result.warnings.begin(),
                         result.warnings.end());
  report.dropped_points = result.dropped_points;
  report.dropped_frames = result.dropped_frames;
  for (const auto& [name, weight] : result.priors.term_weights) {
    report.term_weights.emplace_back(name, weight);
  }
  report.diagnostics = {{"track_step", result.priors.track_step},
                        {"path_acceleration_deg", result.priors.path_acceleration_deg},
                        {"largest_view_angle_deg", result.largest_view_angle_deg},
                        {"refine_converged", result.refine.converged ? 1.0 : 0.0}};
  if (!result.refine.usable) {
    report.warnings.push_back("refinement not usable: " + result.refine.message);
  }
  report.versions = {{"nrsfm", NRSFM_VERSION}, {"ceres", CERES_VERSION_STRING}};

  ShapeErrors errors;
  if (!flags.truth.empty()) {
    NRSFM_RETURN_IF_ERROR(EvaluateShapes(truth, ShapesOfModel(result.model, 0), &errors)
                              .WithContext("--truth"));
    report.metrics = MetricList(errors);
    report.e3d_frame = EvaluationFrameName(errors.e3d_frame);
  }

  WriteOptions write_options;
  write_options.write_ply = flags.ply;
  write_options.overwrite = flags.overwrite;
  NRSFM_RETURN_IF_ERROR(
      WriteReconstruction(flags.output, measurements, result.model, report, write_options));

  out << "K = " << num_bases << ", start: " << report.start_used
      << " (reprojection RMS " << std::setprecision(6) << result.start.reprojection_rms
      << ")\n";
  out << "terms:";
  if (result.priors.term_weights.empty()) out << " none";
  for (const auto& [name, weight] : result.priors.term_weights) {
    out << " " << name << " " << weight;
  }
  out << " (priors " << PriorModeName(options.priors);
  if (options.priors == PriorMode::kAuto) {
    out << ": track step " << std::setprecision(3) << result.priors.track_step
        << (result.priors.video ? ", video" : ", not a video");
    if (result.priors.path_acceleration_deg >= 0) {
      out << ", start's angular acceleration " << result.priors.path_acceleration_deg
          << " deg/frame^2";
    }
  }
  out << ")\n";
  out << std::setprecision(6) << "refine: cost " << result.refine.initial_cost << " -> "
      << result.refine.final_cost << " in " << result.refine.iterations
      << " iterations (" << result.refine.linear_solver << "), "
      << (result.refine.usable ? "usable" : "NOT usable: " + result.refine.message)
      << "\n";
  out << "reprojection RMS " << report.reprojection_rms << ", time "
      << std::setprecision(3) << result.total_seconds << " s\n";
  if (!flags.truth.empty()) {
    out << std::setprecision(6) << "e3D " << errors.e3d << " ("
        << EvaluationFrameName(errors.e3d_frame) << " frame), e3D camera frame "
        << errors.e3d_camera << ", frob_zsign " << errors.frob_zsign;
    if (!std::isnan(errors.rotation_error)) {
      out << ", rotation error " << errors.rotation_error;
    }
    out << ", 3D error " << errors.error3d_pct << " %, z error " << errors.zerror_pct
        << " %\n";
  }
  for (const auto& warning : report.warnings) out << "warning: " << warning << "\n";
  out << "wrote " << flags.output << "\n";
  if (!result.refine.usable) {
    return Status::Error("the refinement did not give a usable solution (" +
                         result.refine.message + "); " + flags.output +
                         " holds the start, marked solution_usable = false");
  }
  return Status::OK();
}

Status RunEvaluate(const CommandFlags& flags, std::ostream& out) {
  if (flags.truth.empty()) return Status::Error("--truth is required");
  if (flags.result.empty()) return Status::Error("--result is required");
  GroundTruth truth, estimate;
  NRSFM_RETURN_IF_ERROR(ReadTruth(flags.truth, flags.truth_var, &truth));
  std::error_code ec;
  if (std::filesystem::is_directory(flags.result, ec)) {
    NRSFM_RETURN_IF_ERROR(ReadResultShapes(flags.result, /*camera=*/0, &estimate));
  } else {
    NRSFM_RETURN_IF_ERROR(ReadPointsCameraCsv(flags.result, /*camera=*/0, &estimate));
  }
  ShapeErrors errors;
  NRSFM_RETURN_IF_ERROR(
      EvaluateShapes(truth, estimate, &errors)
          .WithContext("evaluate " + flags.result + " against " + flags.truth));
  nlohmann::ordered_json line;
  for (const auto& [name, value] : MetricList(errors)) line[name] = value;
  line["e3d_frame"] = EvaluationFrameName(errors.e3d_frame);
  line["F"] = errors.num_frames;
  line["P"] = errors.num_points;
  if (!errors.unscored_frames.empty()) line["unscored_frames"] = errors.unscored_frames;
  if (!errors.unscored_points.empty()) line["unscored_points"] = errors.unscored_points;
  out << line.dump() << "\n";
  return Status::OK();
}

Status RunSynth(const CommandFlags& flags, std::ostream& out) {
  if (flags.output.empty()) return Status::Error("--output PATH.mat is required");
  if (std::filesystem::path(flags.output).extension() != ".mat") {
    return Status::Error("--output must name a .mat file, got '" + flags.output + "'");
  }
  int k = -1;
  if (!flags.K.empty() && (!ParseInt(flags.K, &k) || k < 1)) {
    return Status::Error("--K must be an integer >= 1 for synth, got '" + flags.K + "'");
  }
  NRSFM_RETURN_IF_ERROR(CheckFinite("noise", flags.noise));
  NRSFM_RETURN_IF_ERROR(CheckFinite("missing", flags.missing));
  SyntheticSequence sequence;
  if (flags.dataset == "random") {
    RandomBasisOptions o;
    if (flags.frames != -1) o.num_frames = flags.frames;
    if (flags.points != -1) o.num_points = flags.points;
    if (k != -1) o.num_bases = k;
    o.noise_stddev = flags.noise;
    o.missing_fraction = flags.missing;
    o.seed = flags.seed;
    NRSFM_RETURN_IF_ERROR(GenerateRandomBasis(o, &sequence));
  } else if (flags.dataset == "superquadric") {
    if (k != -1) return Status::Error("--K is fixed (4) for the superquadric dataset");
    SuperquadricOptions o;
    if (flags.frames != -1) o.num_frames = flags.frames;
    if (flags.points != -1) o.num_points = flags.points;
    o.noise_stddev = flags.noise;
    o.missing_fraction = flags.missing;
    o.seed = flags.seed;
    NRSFM_RETURN_IF_ERROR(GenerateSuperquadric(o, &sequence));
  } else if (flags.dataset == "shoe") {
    if (k != -1) return Status::Error("--K is fixed (4) for the shoe dataset");
    if (flags.missing != 0.0) {
      return Status::Error("--missing does not apply to the shoe dataset (its "
                           "missing entries come from self-occlusion)");
    }
    ShoeOptions o;
    if (flags.frames != -1) o.num_frames = flags.frames;
    if (flags.points != -1) o.num_points = flags.points;
    o.num_cameras = flags.cameras == 0 ? 1 : flags.cameras;
    o.noise_stddev = flags.noise;
    o.seed = flags.seed;
    NRSFM_RETURN_IF_ERROR(GenerateShoe(o, &sequence));
  } else {
    return Status::Error("--dataset must be random, superquadric or shoe, got '" +
                         flags.dataset + "'");
  }
  const Measurements& m = sequence.measurements;
  const Model& truth = sequence.truth;
  // W with NaN at missing entries; P3_gt = camera 0's 3D truth in the block
  // layout [x rows of all frames; y rows; z rows], as in the face data.
  Eigen::MatrixXd w = m.W;
  for (int view = 0; view < m.NumViews(); ++view) {
    for (int p = 0; p < m.num_points; ++p) {
      if (!m.visible(view, p)) w.block<2, 1>(2 * view, p).setConstant(NAN);
    }
  }
  const int f = m.num_frames;
  Eigen::MatrixXd p3_gt(3 * f, m.num_points);
  for (int t = 0; t < f; ++t) {
    Eigen::Matrix3Xd x = truth.ShapeInCamera(t, 0);
    x.topRows<2>().colwise() += truth.translations.col(truth.View(t, 0));
    for (int axis = 0; axis < 3; ++axis) p3_gt.row(axis * f + t) = x.row(axis);
  }
  Eigen::MatrixXd rotations(3, truth.NumViews());
  rotations = truth.rotations;
  std::vector<MatVariable> variables = {
      {"W", w, {}},
      {"P3_gt", p3_gt, {}},
      {"rotations_gt", rotations, {}},
      {"weights_gt", truth.weights.transpose(), {}},
      {"basis_gt", truth.basis, {}},
      {"cameras", Eigen::MatrixXd::Constant(1, 1, m.num_cameras), {}}};
  NRSFM_RETURN_IF_ERROR(WriteMat(flags.output, MatVersion::kV5, variables));
  out << "wrote " << flags.output << ": " << flags.dataset << ", F = " << f
      << ", M = " << m.num_cameras << ", P = " << m.num_points
      << ", K = " << truth.num_bases << ", visible " << m.NumVisible() << " of "
      << m.NumViews() * m.num_points << "\n";
  return Status::OK();
}

}  // namespace tools
}  // namespace nrsfm
