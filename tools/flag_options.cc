#include "tools/flag_options.h"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iomanip>
#include <set>
#include <sstream>

#include <Eigen/Core>
#include <ceres/version.h>
#include <nlohmann/json.hpp>

#include "core/result_reader.h"
#include "problems/extra_terms.h"
#include "solvers/drop_unobserved.h"

namespace nrsfm {
namespace tools {
namespace {

#define NRSFM_STRINGIZE2(x) #x
#define NRSFM_STRINGIZE(x) NRSFM_STRINGIZE2(x)
constexpr char kVersion[] =
    NRSFM_VERSION " (Ceres " CERES_VERSION_STRING ", Eigen " NRSFM_STRINGIZE(
        EIGEN_WORLD_VERSION) "." NRSFM_STRINGIZE(EIGEN_MAJOR_VERSION) "." NRSFM_STRINGIZE(EIGEN_MINOR_VERSION) ")";

constexpr const char* kCommands[] = {"reconstruct", "evaluate", "synth", "view"};

bool IsCommand(const std::string& word) {
  for (const char* command : kCommands) {
    if (word == command) return true;
  }
  return false;
}

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

// The Check() of default `Options` with one flag's value set by `set`, its
// error under the flag's name: the library owns the rule, the message names
// the flag the value came from.
template <typename Options, typename Set>
Status CheckFlag(const std::string& flag, Set set) {
  Options options;
  set(&options);
  return options.Check().WithContext("--" + flag);
}

std::string FormatDouble(double value) {
  std::ostringstream s;
  s << std::setprecision(6) << value;
  return s.str();
}

// A flag's value as result.json's "options" write it.
std::string FlagText(const std::string& value) { return value; }
std::string FlagText(int value) { return std::to_string(value); }
std::string FlagText(std::uint64_t value) { return std::to_string(value); }
std::string FlagText(double value) { return FormatDouble(value); }
std::string FlagText(bool value) { return value ? "true" : "false"; }

}  // namespace

const char* VersionString() { return kVersion; }

std::string FlagHelpFor(const std::string& help, const std::string& command) {
  // Split into parts at "; " or ". " followed by a command name and ':' or
  // ' ' (the start of another command's part).
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (std::size_t i = 0; i + 2 < help.size(); ++i) {
    if ((help[i] != ';' && help[i] != '.') || help[i + 1] != ' ') continue;
    std::size_t end = i + 2;
    while (end < help.size() && std::isalpha(static_cast<unsigned char>(help[end]))) ++end;
    if (IsCommand(help.substr(i + 2, end - i - 2)) && end < help.size() &&
        (help[end] == ':' || help[end] == ',' || help[end] == ' ')) {
      parts.push_back(help.substr(start, help[i] == '.' ? i + 1 - start : i - start));
      start = i + 2;
    }
  }
  parts.push_back(help.substr(start));
  std::string out;
  for (const std::string& part : parts) {
    const std::size_t colon = part.find(':');
    if (colon == std::string::npos) continue;
    // "reconstruct, view" or "reconstruct --K auto".
    std::istringstream heads(part.substr(0, colon));
    std::string head;
    bool serves = false;
    std::string qualifier;
    while (std::getline(heads, head, ',')) {
      while (!head.empty() && head.front() == ' ') head.erase(0, 1);
      const std::size_t space = head.find(' ');
      if (head.substr(0, space) == command) {
        serves = true;
        if (space != std::string::npos) qualifier = head.substr(space + 1);
      }
    }
    if (!serves) continue;
    std::string text = part.substr(colon + 1);
    while (!text.empty() && text.front() == ' ') text.erase(0, 1);
    if (!qualifier.empty()) text = "(" + qualifier + ") " + text;
    out += (out.empty() ? "" : " ") + text;
  }
  return out;
}

std::string TermFlagHelp(const ExtraTerm& term) {
  return std::string("reconstruct: weight of the ") + term.meaning + "; " + term.units +
         ", 0 = off (docs/problem.md).";
}

Status CheckSynthOutput(const std::string& output) {
  if (output.empty()) return Status::Error("--output PATH.mat is required");
  if (std::filesystem::path(output).extension() != ".mat") {
    return Status::Error("--output must name a .mat file, got '" + output + "'");
  }
  return Status::OK();
}

Status ParseNumBasesFlag(const std::string& value, bool* auto_k, int* num_bases) {
  *auto_k = value == "auto";
  if (*auto_k) return Status::OK();
  if (!ParseInt(value, num_bases) || *num_bases < 1) {
    return Status::Error("--K must be an integer >= 1 or 'auto', got '" + value + "'");
  }
  return Status::OK();
}

Status ParseHeldBlocks(const std::string& list, ProblemOptions* options) {
  const std::pair<const char*, bool ProblemOptions::*> kinds[] = {
      {"rotations", &ProblemOptions::constant_rotations},
      {"translations", &ProblemOptions::constant_translations},
      {"weights", &ProblemOptions::constant_weights},
      {"basis", &ProblemOptions::constant_basis},
      {"scales", &ProblemOptions::constant_scales},
      {"rig", &ProblemOptions::constant_rig}};
  std::size_t begin = 0;
  while (begin < list.size()) {
    std::size_t end = list.find(',', begin);
    if (end == std::string::npos) end = list.size();
    const std::string name = list.substr(begin, end - begin);
    bool found = false;
    for (const auto& kind : kinds) {
      if (name == kind.first) {
        options->*kind.second = true;
        found = true;
      }
    }
    if (!found) {
      return Status::Error("'" + name +
                           "' is not a kind of block (rotations, translations, "
                           "weights, basis, scales, rig)");
    }
    begin = end + 1;
  }
  return Status::OK();
}

Status BuildReconstructOptions(const CommandFlags& flags, ReconstructOptions* options) {
  NRSFM_RETURN_IF_ERROR(ParseStartMethod(flags.init, &options->start.method)
                            .WithContext("--init"));
  NRSFM_RETURN_IF_ERROR(ParseRobustLoss(flags.robust, &options->problem.robust_loss)
                            .WithContext("--robust"));
  NRSFM_RETURN_IF_ERROR(
      ParseLinearSolver(flags.linear_solver, &options->solver.linear_solver)
          .WithContext("--linear_solver"));
  NRSFM_RETURN_IF_ERROR(ParsePriorMode(flags.priors, &options->priors)
                            .WithContext("--priors"));
  // One flag per extra term (problems/extra_terms.h); 0 leaves the term out.
  // The cameras a term needs are checked once the input is read
  // (CheckTermCameras).
  const std::vector<ExtraTerm>& terms = ExtraTerms();
  for (std::size_t i = 0; i < terms.size(); ++i) {
    const double weight = flags.term_weights[i];
    if (weight == 0.0) continue;
    NRSFM_RETURN_IF_ERROR(CheckFlag<ProblemOptions>(
        terms[i].name, [&](ProblemOptions* o) { o->term_weights[terms[i].name] = weight; }));
    options->problem.term_weights[terms[i].name] = weight;
  }
  if (flags.K == "auto") {
    NRSFM_RETURN_IF_ERROR(CheckFlag<SelectNumBasesOptions>(
        "K_max", [&](SelectNumBasesOptions* o) { o->max_num_bases = flags.K_max; }));
    NRSFM_RETURN_IF_ERROR(CheckFlag<SelectNumBasesOptions>(
        "K_threshold", [&](SelectNumBasesOptions* o) { o->threshold = flags.K_threshold; }));
  }
  // A weight given on the command line is a manual choice of the terms.
  if (!options->problem.term_weights.empty()) options->priors = PriorMode::kManual;
  NRSFM_RETURN_IF_ERROR(ParseHeldBlocks(flags.hold, &options->problem).WithContext("--hold"));
  options->start.seed = flags.seed;
  options->problem.robust_scale = flags.robust_scale;
  options->solver.max_iterations = flags.max_iterations;
  options->solver.num_threads = flags.threads;
  return options->Check();
}

const std::set<std::string>& InputFlags() {
  static const std::set<std::string> names = {"var",       "mask_var", "format",
                                              "cameras",   "frame_key", "part",
                                              "min_confidence"};
  return names;
}

Status BuildInputOptions(const CommandFlags& flags, InputOptions* input) {
  *input = InputOptions();
  input->variable = flags.var;
  input->mask_variable = flags.mask_var;
  input->num_cameras = flags.cameras;
  NRSFM_RETURN_IF_ERROR(ParseInputFormat(flags.format, &input->format).WithContext("--format"));
  NRSFM_RETURN_IF_ERROR(
      ParseKeypointPart(flags.part, &input->keypoints.part).WithContext("--part"));
  NRSFM_RETURN_IF_ERROR(CheckFlag<KeypointOptions>(
      "frame_key", [&](KeypointOptions* o) { o->frame_key = flags.frame_key; }));
  NRSFM_RETURN_IF_ERROR(CheckFlag<KeypointOptions>(
      "min_confidence", [&](KeypointOptions* o) { o->min_confidence = flags.min_confidence; }));
  input->keypoints.frame_key = flags.frame_key;
  input->keypoints.min_confidence = flags.min_confidence;
  return Status::OK();
}

Status RelativeObservationWeights(const Eigen::ArrayXXd& given, const Measurements& measurements,
                                  const std::string& name, Eigen::ArrayXXd* weights) {
  const Measurements& m = measurements;
  if (given.rows() != m.NumViews() || given.cols() != m.num_points) {
    return Status::Error(name + " is " + std::to_string(given.rows()) + " x " +
                         std::to_string(given.cols()) + ", expected " +
                         std::to_string(m.NumViews()) + " x " + std::to_string(m.num_points) +
                         " (one weight per frame and camera, and point)");
  }
  double sum = 0.0;
  for (int view = 0; view < m.NumViews(); ++view) {
    for (int p = 0; p < m.num_points; ++p) {
      if (!m.visible(view, p)) continue;
      const double w = given(view, p);
      if (!(std::isfinite(w) && w >= 0.0)) {
        std::ostringstream msg;
        msg << name << ": the weight of the visible observation of view " << view
            << ", point " << p << " is " << w << "; weights must be finite and >= 0";
        return Status::Error(msg.str());
      }
      sum += w;
    }
  }
  if (!(sum > 0.0)) {
    return Status::Error(name + ": every visible observation has weight 0");
  }
  const double scale = m.NumVisible() / sum;
  *weights = Eigen::ArrayXXd::Zero(m.NumViews(), m.num_points);
  for (int view = 0; view < m.NumViews(); ++view) {
    for (int p = 0; p < m.num_points; ++p) {
      if (m.visible(view, p)) (*weights)(view, p) = given(view, p) * scale;
    }
  }
  return Status::OK();
}

Status MeasurementsFromArrays(const Eigen::MatrixXd& w, const Eigen::MatrixXd& mask, int cameras,
                              Measurements* measurements) {
  if (cameras < 1) return Status::Error("cameras must be >= 1, got " + std::to_string(cameras));
  Eigen::MatrixXd visible_w = w;
  NRSFM_RETURN_IF_ERROR(Measurements::FromMatrixWithNaN(visible_w, cameras, "W", measurements));
  if (mask.size() > 0) {
    NRSFM_RETURN_IF_ERROR(ApplyVisibilityMask(mask, "mask", cameras, &visible_w));
    NRSFM_RETURN_IF_ERROR(
        Measurements::FromMatrixWithNaN(visible_w, cameras, "W", measurements));
  }
  return measurements->Validate().WithContext("W");
}

std::set<std::string> NotArrayReconstructFlags() {
  std::set<std::string> names = ToolOnlyFlags();
  names.insert(InputFlags().begin(), InputFlags().end());
  names.insert({"K", "confidence_weights"});
  return names;
}

Status ArrayReconstructOptions(const Measurements& measurements,
                               const Eigen::ArrayXXd& observation_weights, CommandFlags* flags,
                               ReconstructOptions* options) {
  NRSFM_RETURN_IF_ERROR(CheckTermCameras(*flags, "W", measurements.num_cameras));
  flags->confidence_weights = observation_weights.size() > 0;
  if (!flags->confidence_weights) return Status::OK();
  return RelativeObservationWeights(observation_weights, measurements, "observation_weights",
                                    &options->problem.observation_weights);
}

namespace {

Status ParseFlagText(const std::string& /*name*/, const std::string& text, std::string* value) {
  *value = text;
  return Status::OK();
}

Status ParseFlagText(const std::string& name, const std::string& text, int* value) {
  if (ParseInt(text, value)) return Status::OK();
  return Status::Error(name + " must be an integer, got '" + text + "'");
}

Status ParseFlagText(const std::string& name, const std::string& text, std::uint64_t* value) {
  try {
    std::size_t used = 0;
    const unsigned long long v = std::stoull(text, &used);
    if (used == text.size() && text.find('-') == std::string::npos) {
      *value = static_cast<std::uint64_t>(v);
      return Status::OK();
    }
  } catch (...) {
  }
  return Status::Error(name + " must be an integer in [0, 2^64), got '" + text + "'");
}

Status ParseFlagText(const std::string& name, const std::string& text, double* value) {
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size()) {
      *value = v;
      return Status::OK();
    }
  } catch (...) {
  }
  return Status::Error(name + " must be a number, got '" + text + "'");
}

Status ParseFlagText(const std::string& name, const std::string& text, bool* value) {
  if (text == "true" || text == "1") {
    *value = true;
  } else if (text == "false" || text == "0") {
    *value = false;
  } else {
    return Status::Error(name + " must be true or false, got '" + text + "'");
  }
  return Status::OK();
}

}  // namespace

Status SetFlagFromText(const std::string& name, const std::string& text, CommandFlags* flags) {
#define NRSFM_SET_FLAG(type, flag_name, value, help) \
  if (name == #flag_name) return ParseFlagText(name, text, &flags->flag_name);
  NRSFM_COMMAND_FLAGS(NRSFM_SET_FLAG)
#undef NRSFM_SET_FLAG
  const std::vector<ExtraTerm>& terms = ExtraTerms();
  for (std::size_t i = 0; i < terms.size(); ++i) {
    if (name == terms[i].name) return ParseFlagText(name, text, &flags->term_weights[i]);
  }
  return Status::Error("unknown option '" + name + "'");
}

Status CheckTermCameras(const CommandFlags& flags, const std::string& input,
                        int num_cameras) {
  const std::vector<ExtraTerm>& terms = ExtraTerms();
  for (std::size_t i = 0; i < terms.size(); ++i) {
    if (!(flags.term_weights[i] > 0.0)) continue;
    NRSFM_RETURN_IF_ERROR(terms[i].CheckCameras(num_cameras)
                              .WithContext(input + ": --" + terms[i].name));
  }
  return Status::OK();
}

Status ReadTruth(const std::string& path, const std::string& variable, GroundTruth* truth) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    return ReadPointsCameraCsv(path, /*camera=*/0, truth);
  }
  return ReadGroundTruth(path, variable, truth);
}

namespace {

// The error of RunReconstruction (header) when a weighted run with K bases
// would leave points or frames out.
Status CheckWeightedRunLeavesNothingOut(const Measurements& measurements, int num_bases) {
  Unobserved unobserved;
  if (!FindUnobserved(measurements, num_bases, &unobserved).ok() || unobserved.empty()) {
    return Status::OK();  // nothing left out, or Reconstruct() says what is wrong
  }
  return Status::Error(
      "observation weights (--confidence_weights) with K = " + std::to_string(num_bases) +
      ": the reconstruction would leave points or frames out, which a weighted run cannot "
      "do yet (" + UnobservedWarning(measurements, unobserved) +
      "); reconstruct without the weights, or with a lower --min_confidence or K");
}

}  // namespace

Status RunReconstruction(const CommandFlags& flags, const ReconstructOptions& options,
                         const Measurements& measurements, const std::string& context,
                         ReconstructionRun* run) {
  *run = ReconstructionRun();
  NRSFM_RETURN_IF_ERROR(ParseNumBasesFlag(flags.K, &run->auto_k, &run->num_bases));
  if (options.problem.observation_weights.size() > 0) {
    const int lowest = run->auto_k ? 1 : run->num_bases;
    const int highest = run->auto_k ? flags.K_max : run->num_bases;
    for (int k = lowest; k <= highest; ++k) {
      const Status status = CheckWeightedRunLeavesNothingOut(measurements, k);
      if (!status.ok()) return context.empty() ? status : status.WithContext(context);
    }
  }
  if (run->auto_k) {
    SelectNumBasesOptions select_options;
    select_options.max_num_bases = flags.K_max;
    select_options.threshold = flags.K_threshold;
    NRSFM_RETURN_IF_ERROR(
        SelectNumBases(options, select_options, measurements, &run->selection)
            .WithContext("--K auto"));
    run->num_bases = run->selection.num_bases;
    run->result = std::move(run->selection.reconstruction);
    run->selection.reconstruction = ReconstructResult();
    return Status::OK();
  }
  ReconstructOptions fixed = options;
  fixed.start.num_bases = run->num_bases;
  Status status = Reconstruct(fixed, measurements, &run->result);
  return context.empty() ? status : status.WithContext(context);
}

const std::set<std::string>& ToolOnlyFlags() {
  static const std::set<std::string> names = {"input", "output", "overwrite", "ply",
                                              "quiet", "truth", "truth_var", "result"};
  return names;
}

std::vector<std::pair<std::string, std::string>> OptionList(const CommandFlags& flags,
                                                            int num_bases) {
  std::vector<std::pair<std::string, std::string>> list = {
      {"K", std::to_string(num_bases)}, {"K_flag", flags.K}};
#define NRSFM_ADD_OPTION(type, name, value, help)                                   \
  if (std::string(#name) != "K" && ToolOnlyFlags().count(#name) == 0 &&             \
      !FlagHelpFor(help, "reconstruct").empty()) {                                  \
    list.emplace_back(#name, FlagText(flags.name));                                 \
  }
  NRSFM_COMMAND_FLAGS(NRSFM_ADD_OPTION)
#undef NRSFM_ADD_OPTION
  for (std::size_t i = 0; i < ExtraTerms().size(); ++i) {
    list.emplace_back(ExtraTerms()[i].name, FormatDouble(flags.term_weights[i]));
  }
  return list;
}

ReconstructionReport MakeReport(const CommandFlags& flags, const std::string& input,
                                const ReconstructionRun& run, const ShapeErrors* errors) {
  const ReconstructResult& result = run.result;
  ReconstructionReport report;
  report.input = input;
  report.options = OptionList(flags, run.num_bases);
  report.start_used = StartMethodName(result.start.method);
  report.start_reprojection_rms = result.start.reprojection_rms;
  report.stages.push_back({"initialize", 0.0, 0.0, 0, result.start.seconds});
  if (result.camera_stage) {
    report.stages.push_back({"refine_camera", result.camera_refine.initial_cost,
                             result.camera_refine.final_cost,
                             result.camera_refine.iterations, result.camera_refine.seconds});
  }
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
                        {"track_order", result.priors.track_order},
                        {"path_acceleration_deg", result.priors.path_acceleration_deg},
                        {"camera_num_bases", static_cast<double>(result.priors.camera_num_bases)},
                        {"noise_rms", result.priors.noise_rms},
                        {"largest_view_angle_deg", result.largest_view_angle_deg},
                        {"depth_ratio", result.depth_ratio},
                        {"refine_converged", result.refine.converged ? 1.0 : 0.0},
                        {"camera_refine_converged",
                         result.camera_stage
                             ? (result.camera_refine.converged ? 1.0 : 0.0)
                             : -1.0},
                        {"start_completion_rms", result.start.completion_rms},
                        {"start_subblock_rank1_defect", result.start.subblock_rank1_defect},
                        {"start_rigid_rms", result.start.rigid_rms},
                        {"start_triple_sign_segments",
                         static_cast<double>(result.start.triple_sign_segments)}};
  if (!result.refine.usable) {
    report.warnings.push_back("refinement not usable: " + result.refine.message);
  }
  report.versions = {{"nrsfm", NRSFM_VERSION}, {"ceres", CERES_VERSION_STRING}};
  if (errors != nullptr) {
    report.metrics = MetricList(*errors);
    report.e3d_frame = EvaluationFrameName(errors->e3d_frame);
  }
  return report;
}

std::string EvaluationJson(const ShapeErrors& errors, int num_bases, double rank_floor) {
  nlohmann::ordered_json line;
  for (const auto& [name, value] : MetricList(errors)) line[name] = value;
  line["e3d_frame"] = EvaluationFrameName(errors.e3d_frame);
  if (num_bases > 0 && rank_floor >= 0.0) {
    line["K"] = num_bases;
    line["rank_floor"] = rank_floor;
  }
  line["F"] = errors.num_frames;
  line["P"] = errors.num_points;
  if (!errors.unscored_frames.empty()) line["unscored_frames"] = errors.unscored_frames;
  if (!errors.unscored_points.empty()) line["unscored_points"] = errors.unscored_points;
  return line.dump();
}

namespace {

// Parses "x,y,z" into a vector; false on anything else.
bool ParseVector3(const std::string& text, Eigen::Vector3d* v) {
  std::stringstream in(text);
  std::string item;
  int i = 0;
  while (std::getline(in, item, ',')) {
    if (i == 3) return false;
    try {
      std::size_t used = 0;
      (*v)(i) = std::stod(item, &used);
      if (used != item.size()) return false;
    } catch (...) {
      return false;
    }
    ++i;
  }
  return i == 3;
}

}  // namespace

Status SynthesizeReprojection(const CommandFlags& flags, ReprojectedSequence* sequence,
                              std::vector<MatVariable>* variables) {
  if (flags.input.empty()) {
    return Status::Error("--input is required for --dataset reproject (a .mat "
                         "with S + Rs, P3_gt or X)");
  }
  if (!flags.K.empty() || flags.frames != -1 || flags.points != -1) {
    return Status::Error("--K, --frames and --points do not apply to --dataset "
                         "reproject (the source fixes them)");
  }
  if (flags.noise != 0.0) {
    return Status::Error("--noise does not apply to --dataset reproject; give "
                         "--noise_fraction (of the image size)");
  }
  ReprojectOptions options;
  options.total_rotation_deg = flags.rotation;
  if (!ParseVector3(flags.axis, &options.axis)) {
    return Status::Error("--axis must be three numbers x,y,z, got '" + flags.axis + "'");
  }
  NRSFM_RETURN_IF_ERROR(
      ParseSpeedProfile(flags.profile, &options.profile).WithContext("--profile"));
  options.noise_fraction = flags.noise_fraction;
  options.missing_fraction = flags.missing;
  options.occlusion_radius = flags.occlusion;
  options.seed = flags.seed;
  GroundTruth source;
  NRSFM_RETURN_IF_ERROR(ReadTruth(flags.input, flags.truth_var, &source));
  NRSFM_RETURN_IF_ERROR(GenerateReprojection(source, options, sequence)
                            .WithContext("--input " + flags.input));
  const Measurements& m = sequence->measurements;
  const int f = m.num_frames, p = m.num_points;
  Eigen::MatrixXd w = m.W, s(3 * f, p), rs(2 * f, 3);
  for (int t = 0; t < f; ++t) {
    s.middleRows(3 * t, 3) = sequence->truth.points_in_object[t];
    rs.middleRows(2 * t, 2) = sequence->truth.rotations[t].topRows<2>();
  }
  *variables = {
      {"W", w, {}},
      {"S", s, {}},
      {"Rs", rs, {}},
      {"cameras", Eigen::MatrixXd::Constant(1, 1, 1.0), {}},
      {"image_size", Eigen::MatrixXd::Constant(1, 1, sequence->image_size), {}},
      {"noise_stddev", Eigen::MatrixXd::Constant(1, 1, sequence->noise_stddev), {}}};
  // The skeleton edges of the source, for nrsfm view.
  Eigen::MatrixXd list;
  if (std::filesystem::path(flags.input).extension() == ".mat" &&
      ReadMatVariable(flags.input, "list", &list).ok()) {
    variables->push_back({"list", list, {}});
  }
  return Status::OK();
}

Status Synthesize(const CommandFlags& flags, SyntheticSequence* sequence) {
  int k = -1;
  if (!flags.K.empty() && (!ParseInt(flags.K, &k) || k < 1)) {
    return Status::Error("--K must be an integer >= 1 for synth, got '" + flags.K + "'");
  }
  NRSFM_RETURN_IF_ERROR(CheckFinite("noise", flags.noise));
  NRSFM_RETURN_IF_ERROR(CheckFinite("missing", flags.missing));
  // --frames, --noise, --missing and --seed of the random and superquadric data.
  const auto set_sequence = [&flags](SmoothSequenceOptions* o) {
    if (flags.frames != -1) o->num_frames = flags.frames;
    o->noise_stddev = flags.noise;
    o->missing_fraction = flags.missing;
    o->seed = flags.seed;
  };
  if (flags.dataset == "random") {
    RandomBasisOptions o;
    set_sequence(&o);
    if (flags.points != -1) o.num_points = flags.points;
    if (k != -1) o.num_bases = k;
    return GenerateRandomBasis(o, sequence);
  }
  if (flags.dataset == "superquadric") {
    if (k != -1) return Status::Error("--K is fixed (4) for the superquadric dataset");
    SuperquadricOptions o;
    set_sequence(&o);
    if (flags.points != -1) o.num_points = flags.points;
    return GenerateSuperquadric(o, sequence);
  }
  if (flags.dataset == "shoe") {
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
    return GenerateShoe(o, sequence);
  }
  return Status::Error("--dataset must be random, superquadric, shoe or reproject, got '" +
                       flags.dataset + "'");
}

std::vector<MatVariable> SyntheticVariables(const SyntheticSequence& sequence) {
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
  return {{"W", w, {}},
          {"P3_gt", p3_gt, {}},
          {"rotations_gt", rotations, {}},
          {"weights_gt", truth.weights.transpose(), {}},
          {"basis_gt", truth.basis, {}},
          {"cameras", Eigen::MatrixXd::Constant(1, 1, m.num_cameras), {}}};
}

}  // namespace tools
}  // namespace nrsfm
