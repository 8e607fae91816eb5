#include "tools/commands.h"

#include <Eigen/Core>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/eval/metrics.h"
#include "core/eval/uncertainty_metrics.h"
#include "core/io/ground_truth.h"
#include "core/io/mat_io.h"
#include "core/io/read_measurements.h"
#include "core/io/result_reader.h"
#include "core/io/result_writer.h"
#include "core/synthetic/synthetic.h"
#include "tools/flag_table.h"
#include "tools/reconstruction_steps.h"
#include "tools/synth_steps.h"

namespace nrsfm {
namespace tools {
namespace {

// The warning of an input whose frames or points the reader renumbered
// (Measurements::frame_ids, point_ids), "" otherwise.
std::string RenumberedInputWarning(const Measurements& m) {
  if (m.frame_ids.empty() && m.point_ids.empty()) return "";
  return "the list's largest indices (frame " +
         std::to_string(m.frame_ids.back()) + ", point " +
         std::to_string(m.point_ids.back()) +
         ") would make too large a W for it: the result holds only the " +
         std::to_string(m.num_frames) + " frames and " +
         std::to_string(m.num_points) + " points it mentions, numbered 0.." +
         std::to_string(m.num_frames - 1) + " and 0.." +
         std::to_string(m.num_points - 1) +
         " in increasing order of their index (result.json: input_frames and "
         "input_points "
         "give each one's index in the list)";
}

}  // namespace

Status RunReconstruct(const CommandFlags& flags, std::ostream& out,
                      std::ostream& progress) {
  if (flags.input.empty()) return Status::Error("--input is required");
  if (flags.output.empty()) return Status::Error("--output is required");
  if (flags.K.empty())
    return Status::Error("--K is required (an integer >= 1 or 'auto')");
  FlagTargets targets;
  NRSFM_RETURN_IF_ERROR(ApplyFlags(flags, &targets));
  ReconstructOptions& options = targets.reconstruct;

  // Refuse an output that cannot be written before spending time solving.
  if (!flags.overwrite) {
    std::error_code ec;
    if (std::filesystem::exists(flags.output, ec) &&
        !(std::filesystem::is_directory(flags.output, ec) &&
          std::filesystem::is_empty(flags.output, ec))) {
      return Status::Error(
          "output '" + flags.output +
          "' exists and is not an empty directory (use --overwrite "
          "to replace an earlier result)");
    }
  }

  Measurements measurements;
  InputDetails details;
  NRSFM_RETURN_IF_ERROR(
      ReadMeasurements(flags.input, targets.input, &measurements, &details));
  NRSFM_RETURN_IF_ERROR(
      CheckTermCameras(flags, flags.input, measurements.num_cameras));
  if (flags.confidence_weights) {
    if (details.confidence.size() == 0) {
      return Status::Error(
          "--confidence_weights: " + flags.input +
          " holds no detector scores (only keypoint inputs do: COCO "
          "results .json, OpenPose folders)");
    }
    NRSFM_RETURN_IF_ERROR(RelativeObservationWeights(
        details.confidence, measurements, flags.input + ": confidence",
        &options.problem.observation_weights));
  }

  GroundTruth truth;
  if (!flags.truth.empty()) {
    NRSFM_RETURN_IF_ERROR(ReadTruth(flags.truth, flags.truth_var, &truth));
    if (truth.NumFrames() != measurements.num_frames ||
        truth.NumPoints() != measurements.num_points) {
      return Status::Error(
          "--truth '" + flags.truth +
          "' has F = " + std::to_string(truth.NumFrames()) +
          ", P = " + std::to_string(truth.NumPoints()) +
          " but the input has F = " + std::to_string(measurements.num_frames) +
          ", P = " + std::to_string(measurements.num_points) +
          (measurements.frame_ids.empty()
               ? ""
               : " (the frames and points the list mentions)"));
    }
  }

  out << "input: " << flags.input << "  F = " << measurements.num_frames
      << ", M = " << measurements.num_cameras
      << ", P = " << measurements.num_points << ", visible "
      << measurements.NumVisible() << " of "
      << measurements.NumViews() * measurements.num_points << "\n";

  if (!flags.quiet) {
    options.solver.progress = [&progress](const IterationReport& report) {
      progress << "  iteration " << std::setw(4) << report.iteration
               << "  cost " << std::setprecision(6) << std::scientific
               << report.cost << std::defaultfloat << "  " << std::fixed
               << std::setprecision(2) << report.seconds << " s"
               << std::defaultfloat << "\n";
    };
  }

  ReconstructionRun run;
  const Status solved =
      RunReconstruction(targets, measurements, flags.input, &run);
  if (!solved.ok() && !measurements.frame_ids.empty()) {
    return Status::Error(
        solved.message() +
        " (F and P count the frames and points the list mentions; its largest "
        "indices are frame " +
        std::to_string(measurements.frame_ids.back()) + ", point " +
        std::to_string(measurements.point_ids.back()) + ")");
  }
  NRSFM_RETURN_IF_ERROR(solved);
  const ReconstructResult& result = run.result;
  if (run.auto_k) {
    const SelectNumBasesResult& selection = run.selection;
    out << "K selection (noise estimate " << std::setprecision(4)
        << selection.noise_stddev << " per coordinate):\n";
    out << "   K   reprojection RMS   expected noise RMS   time [s]\n";
    for (const auto& c : selection.curve) {
      out << std::setw(4) << c.num_bases << "   ";
      if (c.ok) {
        out << std::setw(16) << std::setprecision(6) << c.reprojection_rms
            << "   " << std::setw(18) << c.expected_rms << "   " << std::setw(8)
            << std::setprecision(3) << c.seconds
            << (c.num_bases == selection.num_bases ? "   <- chosen" : "")
            << "\n";
      } else {
        out << "failed: " << c.message << "\n";
      }
    }
  }
  const int num_bases = run.num_bases;

  ShapeErrors errors;
  if (!flags.truth.empty()) {
    NRSFM_RETURN_IF_ERROR(
        EvaluateShapes(truth, ShapesOfModel(result.model, 0), &errors)
            .WithContext("--truth"));
  }
  ReconstructionReport report = MakeReport(
      flags, flags.input, run, flags.truth.empty() ? nullptr : &errors);
  const std::string renumbered = RenumberedInputWarning(measurements);
  if (!renumbered.empty())
    report.warnings.insert(report.warnings.begin(), renumbered);
  report.warnings.insert(report.warnings.begin(), details.warnings.begin(),
                         details.warnings.end());

  WriteOptions write_options;
  write_options.write_ply = flags.ply;
  write_options.overwrite = flags.overwrite;
  write_options.num_threads = flags.threads;
  NRSFM_RETURN_IF_ERROR(WriteReconstruction(
      flags.output, measurements, result.model, report, write_options));
  if (run.uncertainty_requested && run.uncertainty_status.ok()) {
    NRSFM_RETURN_IF_ERROR(
        WriteCovariances(flags.output, measurements.num_frames,
                         measurements.num_cameras, measurements.num_points,
                         run.uncertainty.points, run.uncertainty.rotations));
    const UncertaintySummary& u = run.uncertainty_summary;
    out << "uncertainty: point std median " << std::setprecision(4)
        << u.median_point_std << ", largest " << u.max_point_std
        << ", worst frame " << u.worst_frame << "; depth std median "
        << u.median_depth_std << " (" << std::setprecision(3)
        << 100 * u.relative_depth_std << " % of the extent); noise std "
        << std::setprecision(4) << run.uncertainty.noise_std
        << (run.uncertainty.noise_estimated ? " (estimated)" : " (given)")
        << "; " << std::setprecision(3) << run.uncertainty.seconds << " s\n";
  }

  out << "K = " << num_bases << ", start: " << report.start_used
      << " (reprojection RMS " << std::setprecision(6)
      << result.start.reprojection_rms << ")\n";
  out << "terms:";
  if (result.priors.term_weights.empty()) out << " none";
  for (const auto& [name, weight] : result.priors.term_weights) {
    out << " " << name << " " << weight;
  }
  out << " (priors " << PriorModeName(options.priors);
  if (options.priors == PriorMode::kAuto) {
    out << ": track order " << std::setprecision(3) << result.priors.track_order
        << (result.priors.video ? ", video" : ", not a video");
    if (result.priors.deformation_coherence >= 0) {
      out << ", start's deformation coherence "
          << result.priors.deformation_coherence;
    }
    if (result.priors.path_acceleration_deg >= 0) {
      out << ", start's path acceleration "
          << result.priors.path_acceleration_deg << " deg/frame^2";
    }
    if (result.camera_stage) {
      out << ", camera from K = " << result.priors.camera_num_bases;
    }
  }
  out << ")\n";
  if (result.camera_stage) {
    out << std::setprecision(6)
        << "refine camera (K = " << result.priors.camera_num_bases << "): cost "
        << result.camera_refine.initial_cost << " -> "
        << result.camera_refine.final_cost << " in "
        << result.camera_refine.iterations << " iterations\n";
  }
  out << std::setprecision(6) << "refine: cost " << result.refine.initial_cost
      << " -> " << result.refine.final_cost << " in "
      << result.refine.iterations << " iterations ("
      << result.refine.linear_solver << "), "
      << (result.refine.usable ? "usable"
                               : "NOT usable: " + result.refine.message)
      << "\n";
  out << "reprojection RMS " << report.reprojection_rms << ", time "
      << std::setprecision(3) << result.total_seconds << " s\n";
  if (!flags.truth.empty()) {
    out << std::setprecision(6) << "e3D " << errors.e3d << " ("
        << EvaluationFrameName(errors.e3d_frame) << " frame; with one scale "
        << errors.e3d_scaled << "), e3D camera frame " << errors.e3d_camera
        << ", frob_zsign " << errors.frob_zsign;
    if (!std::isnan(errors.rotation_error)) {
      out << ", rotation error " << errors.rotation_error;
    }
    out << ", 3D error " << errors.error3d_pct << " %, z error "
        << errors.zerror_pct << " %\n";
  }
  for (const auto& warning : report.warnings)
    out << "warning: " << warning << "\n";
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
    NRSFM_RETURN_IF_ERROR(
        ReadResultShapes(flags.result, /*camera=*/0, &estimate));
  } else {
    NRSFM_RETURN_IF_ERROR(
        ReadPointsCameraCsv(flags.result, /*camera=*/0, &estimate));
  }
  ShapeErrors errors;
  NRSFM_RETURN_IF_ERROR(
      EvaluateShapes(truth, estimate, &errors)
          .WithContext("evaluate " + flags.result + " against " + flags.truth));
  // The rank-K floor beside an object-frame e3D: K from --K, else from the
  // result directory's result.json.
  int num_bases = 0;
  if (!flags.K.empty()) {
    NumBasesFlag k;
    NRSFM_RETURN_IF_ERROR(ParseNumBasesFlag(flags.K, &k).WithContext("--K"));
    if (k.automatic)
      return Status::Error("--K: evaluate needs the result's K, not 'auto'");
    num_bases = k.value;
  } else if (std::filesystem::is_directory(flags.result, ec)) {
    NRSFM_RETURN_IF_ERROR(ReadResultNumBases(flags.result, &num_bases));
  }
  double floor = -1.0;
  if (num_bases > 0 && errors.e3d_frame == EvaluationFrame::kObject) {
    floor = ComputeRankFloorE3D(truth.points_in_object, num_bases);
  }
  std::string line = EvaluationJson(errors, num_bases, floor);
  // A result with --uncertainty: how well its covariances describe the
  // actual errors (core/eval/uncertainty_metrics.h).
  if (std::filesystem::exists(
          std::filesystem::path(flags.result) / "points_covariance.csv", ec)) {
    std::vector<Eigen::Matrix3d> covariances;
    NRSFM_RETURN_IF_ERROR(ReadPointsCovarianceCsv(
        flags.result, /*camera=*/0, estimate.NumFrames(), estimate.NumPoints(),
        &covariances));
    if (truth.NumFrames() == estimate.NumFrames() &&
        truth.NumPoints() == estimate.NumPoints()) {
      // A perspective answer is fixed up to scale: aligned with one scale.
      CameraModel camera = CameraModel::kWeakPerspective;
      Eigen::Matrix4Xd intrinsics;
      NRSFM_RETURN_IF_ERROR(
          ReadResultCamera(flags.result, &camera, &intrinsics));
      const UncertaintyCalibration score = ScoreUncertainty(
          truth.points_in_camera, estimate.points_in_camera, covariances,
          /*with_scale=*/camera == CameraModel::kPerspective);
      nlohmann::ordered_json json = nlohmann::ordered_json::parse(line);
      json["uncertainty_inside_95"] = score.inside_95;
      json["uncertainty_mean_mahalanobis2"] = score.mean_mahalanobis_squared;
      json["uncertainty_spearman_per_point"] = score.spearman_per_point;
      json["uncertainty_spearman_per_entry"] = score.spearman_per_entry;
      line = json.dump();
    }
  }
  out << line << "\n";
  return Status::OK();
}

// synth --dataset reproject (tools/synth_steps.h): the file and one line.
Status RunSynthReproject(const CommandFlags& flags, std::ostream& out) {
  ReprojectedSequence sequence;
  std::vector<MatVariable> variables;
  NRSFM_RETURN_IF_ERROR(SynthesizeReprojection(flags, &sequence, &variables));
  NRSFM_RETURN_IF_ERROR(WriteMat(flags.output, MatVersion::kV5, variables));
  const Measurements& m = sequence.measurements;
  out << "wrote " << flags.output << ": reproject of " << flags.input
      << ", F = " << m.num_frames << ", P = " << m.num_points << ", rotation "
      << flags.rotation << " deg (" << flags.profile << "), image size "
      << std::setprecision(4) << sequence.image_size << ", noise std "
      << sequence.noise_stddev << ", visible " << m.NumVisible() << " of "
      << m.num_frames * m.num_points << "\n";
  return Status::OK();
}

Status RunSynth(const CommandFlags& flags, std::ostream& out) {
  NRSFM_RETURN_IF_ERROR(CheckSynthOutput(flags.output));
  NRSFM_RETURN_IF_ERROR(CheckSynthDataset(flags.dataset));
  if (flags.dataset == "reproject") return RunSynthReproject(flags, out);
  SyntheticSequence sequence;
  NRSFM_RETURN_IF_ERROR(Synthesize(flags, &sequence));
  NRSFM_RETURN_IF_ERROR(
      WriteMat(flags.output, MatVersion::kV5, SyntheticVariables(sequence)));
  const Measurements& m = sequence.measurements;
  out << "wrote " << flags.output << ": " << flags.dataset
      << ", F = " << m.num_frames << ", M = " << m.num_cameras
      << ", P = " << m.num_points << ", K = " << sequence.truth.num_bases
      << ", visible " << m.NumVisible() << " of " << m.NumViews() * m.num_points
      << "\n";
  return Status::OK();
}

}  // namespace tools
}  // namespace nrsfm
