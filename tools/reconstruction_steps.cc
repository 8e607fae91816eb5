#include "tools/reconstruction_steps.h"

#include <ceres/version.h>

#include <Eigen/Core>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/io/result_reader.h"
#include "problems/extra_terms.h"
#include "solvers/pipeline/drop_unobserved.h"
#include "tools/flag_table.h"

namespace nrsfm {
namespace tools {
namespace {

#define NRSFM_STRINGIZE2(x) #x
#define NRSFM_STRINGIZE(x) NRSFM_STRINGIZE2(x)
constexpr char kVersion[] = NRSFM_VERSION
    " (Ceres " CERES_VERSION_STRING
    ", Eigen " NRSFM_STRINGIZE(EIGEN_WORLD_VERSION) "." NRSFM_STRINGIZE(
        EIGEN_MAJOR_VERSION) "." NRSFM_STRINGIZE(EIGEN_MINOR_VERSION) ")";

}  // namespace

const char* VersionString() { return kVersion; }

Status RelativeObservationWeights(const Eigen::ArrayXXd& given,
                                  const Measurements& measurements,
                                  const std::string& name,
                                  Eigen::ArrayXXd* weights) {
  const Measurements& m = measurements;
  if (given.rows() != m.NumViews() || given.cols() != m.num_points) {
    return Status::Error(name + " is " + std::to_string(given.rows()) + " x " +
                         std::to_string(given.cols()) + ", expected " +
                         std::to_string(m.NumViews()) + " x " +
                         std::to_string(m.num_points) +
                         " (one weight per frame and camera, and point)");
  }
  double sum = 0.0;
  for (int view = 0; view < m.NumViews(); ++view) {
    for (int p = 0; p < m.num_points; ++p) {
      if (!m.visible(view, p)) continue;
      const double w = given(view, p);
      if (!(std::isfinite(w) && w >= 0.0)) {
        std::ostringstream msg;
        msg << name << ": the weight of the visible observation of view "
            << view << ", point " << p << " is " << w
            << "; weights must be finite and >= 0";
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

Status MeasurementsFromArrays(const Eigen::MatrixXd& w,
                              const Eigen::MatrixXd& mask, int cameras,
                              Measurements* measurements) {
  if (cameras < 1)
    return Status::Error("cameras must be >= 1, got " +
                         std::to_string(cameras));
  Eigen::MatrixXd visible_w = w;
  NRSFM_RETURN_IF_ERROR(
      Measurements::FromMatrixWithNaN(visible_w, cameras, "W", measurements));
  if (mask.size() > 0) {
    NRSFM_RETURN_IF_ERROR(
        ApplyVisibilityMask(mask, "mask", cameras, &visible_w));
    NRSFM_RETURN_IF_ERROR(
        Measurements::FromMatrixWithNaN(visible_w, cameras, "W", measurements));
  }
  return measurements->Validate().WithContext("W");
}

Status ArrayReconstructOptions(const Measurements& measurements,
                               const Eigen::ArrayXXd& observation_weights,
                               CommandFlags* flags, FlagTargets* targets) {
  NRSFM_RETURN_IF_ERROR(
      CheckTermCameras(*flags, "W", measurements.num_cameras));
  flags->confidence_weights = observation_weights.size() > 0;
  if (!flags->confidence_weights) return Status::OK();
  return RelativeObservationWeights(
      observation_weights, measurements, "observation_weights",
      &targets->reconstruct.problem.observation_weights);
}

Status CheckTermCameras(const CommandFlags& flags, const std::string& input,
                        int num_cameras) {
  const std::vector<ExtraTerm>& terms = ExtraTerms();
  for (std::size_t i = 0; i < terms.size(); ++i) {
    if (!(flags.term_weights[i] > 0.0)) continue;
    NRSFM_RETURN_IF_ERROR(terms[i]
                              .CheckCameras(num_cameras)
                              .WithContext(input + ": --" + terms[i].name));
  }
  return Status::OK();
}

Status ReadTruth(const std::string& path, const std::string& variable,
                 GroundTruth* truth) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    return ReadPointsCameraCsv(path, /*camera=*/0, truth);
  }
  return ReadGroundTruth(path, variable, truth);
}

namespace {

// The error of RunReconstruction (header) when a weighted run with K bases
// would leave points or frames out.
Status CheckWeightedRunLeavesNothingOut(const Measurements& measurements,
                                        int num_bases) {
  Unobserved unobserved;
  if (!FindUnobserved(measurements, num_bases, &unobserved).ok() ||
      unobserved.empty()) {
    return Status::OK();  // nothing left out, or Reconstruct() says what is
                          // wrong
  }
  return Status::Error("observation weights (--confidence_weights) with K = " +
                       std::to_string(num_bases) +
                       ": the reconstruction would leave points or frames out, "
                       "which a weighted run cannot "
                       "do yet (" +
                       UnobservedWarning(measurements, unobserved) +
                       "); reconstruct without the weights, or with a lower "
                       "--min_confidence or K");
}

}  // namespace

Status RunReconstruction(const FlagTargets& targets,
                         const Measurements& measurements,
                         const std::string& context, ReconstructionRun* run) {
  *run = ReconstructionRun();
  if (!targets.num_bases.given) {
    return Status::Error("--K is required (an integer >= 1 or 'auto')");
  }
  const ReconstructOptions& options = targets.reconstruct;
  run->auto_k = targets.num_bases.automatic;
  run->num_bases = targets.num_bases.value;
  if (options.problem.observation_weights.size() > 0) {
    const int lowest = run->auto_k ? 1 : run->num_bases;
    const int highest =
        run->auto_k ? targets.select.max_num_bases : run->num_bases;
    for (int k = lowest; k <= highest; ++k) {
      const Status status = CheckWeightedRunLeavesNothingOut(measurements, k);
      if (!status.ok())
        return context.empty() ? status : status.WithContext(context);
    }
  }
  if (run->auto_k) {
    NRSFM_RETURN_IF_ERROR(
        SelectNumBases(options, targets.select, measurements, &run->selection)
            .WithContext("--K auto"));
    run->num_bases = run->selection.num_bases;
    run->result = std::move(run->selection.reconstruction);
    run->selection.reconstruction = ReconstructResult();
  } else {
    ReconstructOptions fixed = options;
    fixed.start.num_bases = run->num_bases;
    const Status status = Reconstruct(fixed, measurements, &run->result);
    if (!status.ok()) {
      return context.empty() ? status : status.WithContext(context);
    }
  }
  if (targets.uncertainty.compute) {
    ReconstructOptions used = options;
    used.start.num_bases = run->num_bases;
    run->uncertainty_requested = true;
    UncertaintyOptions uncertainty = targets.uncertainty.options;
    uncertainty.num_threads = options.solver.num_threads;
    run->uncertainty_status = ComputeResultUncertainty(
        uncertainty, used, measurements, run->result, &run->uncertainty);
    if (run->uncertainty_status.ok()) {
      run->uncertainty_summary =
          SummariseUncertainty(run->uncertainty, run->result.model);
    }
  }
  return Status::OK();
}

ReconstructionReport MakeReport(const CommandFlags& flags,
                                const std::string& input,
                                const ReconstructionRun& run,
                                const ShapeErrors* errors) {
  const ReconstructResult& result = run.result;
  ReconstructionReport report;
  report.input = input;
  report.options = OptionList(flags, run.num_bases);
  report.start_used = StartMethodName(result.start.method);
  report.start_reprojection_rms = result.start.reprojection_rms;
  report.stages.push_back({"start", 0.0, 0.0, 0, result.start.seconds});
  if (result.camera_stage) {
    report.stages.push_back({"refine_camera", result.camera_refine.initial_cost,
                             result.camera_refine.final_cost,
                             result.camera_refine.iterations,
                             result.camera_refine.seconds});
  }
  const bool perspective = result.model.camera == CameraModel::kPerspective;
  const RefineSummary& weak =
      perspective ? result.weak_perspective_refine : result.refine;
  report.stages.push_back({"refine", weak.initial_cost, weak.final_cost,
                           weak.iterations, weak.seconds});
  if (perspective) {
    report.stages.push_back({"refine_perspective", result.refine.initial_cost,
                             result.refine.final_cost, result.refine.iterations,
                             result.refine.seconds});
  }
  report.reprojection_rms = result.refine.usable
                                ? result.refine.reprojection_rms
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
  report.diagnostics = {
      {"track_step", result.priors.track_step},
      {"track_order", result.priors.track_order},
      {"path_acceleration_deg", result.priors.path_acceleration_deg},
      {"camera_num_bases", static_cast<double>(result.priors.camera_num_bases)},
      {"noise_rms", result.priors.noise_rms},
      {"deformation_coherence", result.priors.deformation_coherence},
      {"exactly_low_rank", result.priors.exactly_low_rank ? 1.0 : 0.0},
      {"prior_fit_ratio", result.priors.prior_fit_ratio},
      {"rigid_reprojection_rms", result.rigid_reprojection_rms},
      {"rigid_depth_ratio", result.rigid_depth_ratio},
      {"repair_strength", result.repair_strength},
      {"largest_view_angle_deg", result.largest_view_angle_deg},
      {"depth_ratio", result.depth_ratio},
      {"refine_converged", result.refine.converged ? 1.0 : 0.0},
      {"camera_refine_converged",
       result.camera_stage ? (result.camera_refine.converged ? 1.0 : 0.0)
                           : -1.0},
      {"start_completion_rms", result.start.completion_rms},
      {"start_subblock_rank1_defect", result.start.subblock_rank1_defect},
      {"start_rigid_rms", result.start.rigid_rms},
      {"start_triple_sign_segments",
       static_cast<double>(result.start.triple_sign_segments)}};
  if (run.auto_k) {
    // --K auto: the noise the curve was judged against and how many K were
    // reconstructed for it (solvers/pipeline/select_num_bases.h).
    report.diagnostics.emplace_back("k_selection_noise_stddev",
                                    run.selection.noise_stddev);
    report.diagnostics.emplace_back(
        "k_selection_tried", static_cast<double>(run.selection.curve.size()));
  }
  if (!result.refine.usable) {
    report.warnings.push_back("refinement not usable: " +
                              result.refine.message);
  }
  if (run.uncertainty_requested && !run.uncertainty_status.ok()) {
    report.warnings.push_back(run.uncertainty_status.message() +
                              "; no covariance written");
  } else if (run.uncertainty_requested) {
    const UncertaintySummary& u = run.uncertainty_summary;
    report.diagnostics.insert(
        report.diagnostics.end(),
        {{"uncertainty_noise_std", run.uncertainty.noise_std},
         {"uncertainty_median_point_std", u.median_point_std},
         {"uncertainty_max_point_std", u.max_point_std},
         {"uncertainty_worst_frame", static_cast<double>(u.worst_frame)},
         {"uncertainty_worst_frame_std", u.worst_frame_std},
         {"uncertainty_median_depth_std", u.median_depth_std},
         {"uncertainty_relative_depth_std", u.relative_depth_std},
         {"uncertainty_seconds", run.uncertainty.seconds}});
    for (std::string& warning : report.warnings) {
      if (warning.rfind("little rotation", 0) != 0) continue;
      std::ostringstream quote;
      quote << std::setprecision(3) << "; the predicted depth std of a point "
            << "is " << u.median_depth_std << " (median, "
            << 100 * u.relative_depth_std << " % of the shape's extent)";
      warning += quote.str();
    }
  }
  report.versions = {{"nrsfm", NRSFM_VERSION}, {"ceres", CERES_VERSION_STRING}};
  if (errors != nullptr) {
    report.metrics = MetricList(*errors);
    report.e3d_frame = EvaluationFrameName(errors->e3d_frame);
  }
  return report;
}

std::string EvaluationJson(const ShapeErrors& errors, int num_bases,
                           double rank_floor) {
  nlohmann::ordered_json line;
  for (const auto& [name, value] : MetricList(errors)) line[name] = value;
  line["e3d_frame"] = EvaluationFrameName(errors.e3d_frame);
  if (num_bases > 0 && rank_floor >= 0.0) {
    line["K"] = num_bases;
    line["rank_floor"] = rank_floor;
  }
  line["F"] = errors.num_frames;
  line["P"] = errors.num_points;
  if (!errors.unscored_frames.empty())
    line["unscored_frames"] = errors.unscored_frames;
  if (!errors.unscored_points.empty())
    line["unscored_points"] = errors.unscored_points;
  return line.dump();
}

}  // namespace tools
}  // namespace nrsfm
