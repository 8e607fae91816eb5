// robustness suite: the real sequences' 3-D truth re-projected under other
// camera paths (core/synthetic/synthetic.h, GenerateReprojection): slow
// rotation (60°, 90°, 120° in total, constant speed), uneven speed (ramp,
// stop-and-go over 90°), noise of 1, 3, 5 % of the image size and 30 % of the
// entries missing at random (both over 120°), each reconstructed with the
// default pipeline at the published K. Scored in the camera frame by the
// relative Frobenius error with a per-frame depth sign (Lee et al.'s protocol
// for their slow-rotation experiments), next to a flat answer (the truth with
// z = 0) and Lee et al.'s numbers (CVPR 2016, Table 2), and in the object
// frame by e3D (the new truth keeps the source's object frame: its S, or its
// camera-frame points for face). Also whether the result carries the little
// rotation warning (solvers/pipeline/reconstruct.h).
//
// perspective suite (in this file: the same re-projection): the truth under
// a pinhole camera at distance ratios 1.5, 3, 10, 30 (ReprojectOptions::
// distance_ratio, 0.1 % noise, about 0.5 px), and the real perspective
// sequences of <datasets>/perspective (W in pixels, Kcam, camera-frame X) at
// K 1, 2, 3, each reconstructed by the default pipeline with the weak-
// perspective and with the perspective camera, scored by e3D with one
// global scale in the camera frame (ComputeScaledE3D) beside a flat answer.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "bench/bench_config.h"
#include "bench/mocap_data.h"
#include "bench/report.h"
#include "bench/run_evaluate.h"
#include "bench/suites.h"
#include "core/eval/metrics.h"
#include "core/io/ground_truth.h"
#include "core/io/read_measurements.h"
#include "core/math/parallel_for.h"
#include "core/synthetic/synthetic.h"

namespace nrsfm {
namespace bench {
namespace {

struct Case {
  std::string name;
  ReprojectOptions options;
};

std::vector<Case> Cases(bool quick) {
  const auto make = [](const std::string& name, double rotation,
                       SpeedProfile profile, double noise, double missing) {
    Case c;
    c.name = name;
    c.options.total_rotation_deg = rotation;
    c.options.profile = profile;
    c.options.noise_fraction = noise;
    c.options.missing_fraction = missing;
    return c;
  };
  if (quick) {
    return {make("rot60", 60, SpeedProfile::kConstant, 0, 0),
            make("rot120", 120, SpeedProfile::kConstant, 0, 0),
            make("noise3", 120, SpeedProfile::kConstant, 0.03, 0),
            make("missing30", 120, SpeedProfile::kConstant, 0, 0.3)};
  }
  return {make("rot60", 60, SpeedProfile::kConstant, 0, 0),
          make("rot90", 90, SpeedProfile::kConstant, 0, 0),
          make("rot120", 120, SpeedProfile::kConstant, 0, 0),
          make("ramp90", 90, SpeedProfile::kRamp, 0, 0),
          make("stopgo90", 90, SpeedProfile::kStopAndGo, 0, 0),
          make("noise1", 120, SpeedProfile::kConstant, 0.01, 0),
          make("noise3", 120, SpeedProfile::kConstant, 0.03, 0),
          make("noise5", 120, SpeedProfile::kConstant, 0.05, 0),
          make("missing30", 120, SpeedProfile::kConstant, 0, 0.3)};
}

// Lee, Choi and Oh, CVPR 2016, Table 2: the best of the methods compared
// there, relative Frobenius error with per-frame z-sign, constant slow
// rotation of 60 / 90 / 120 degrees in total.
const std::map<std::string, std::map<std::string, double>>& LeeSlowRotation() {
  static const std::map<std::string, std::map<std::string, double>> table = {
      {"drink", {{"rot60", 0.0411}, {"rot90", 0.0353}, {"rot120", 0.0304}}},
      {"pickup", {{"rot60", 0.1281}, {"rot90", 0.0918}, {"rot120", 0.0964}}},
      {"yoga", {{"rot60", 0.1845}, {"rot90", 0.1190}, {"rot120", 0.1115}}},
  };
  return table;
}

// The flat answer: the camera-frame truth with every depth set to zero.
double FlatFrobenius(const GroundTruth& truth) {
  std::vector<Eigen::Matrix3Xd> flat = truth.points_in_camera;
  for (Eigen::Matrix3Xd& x : flat) x.row(2).setZero();
  return ComputeFrobeniusZSign(truth.points_in_camera, flat);
}

bool HasLittleRotationWarning(const RunOutcome& o) {
  for (const std::string& warning : o.warnings) {
    if (warning.rfind("little rotation", 0) == 0) return true;
  }
  return false;
}

}  // namespace

Status RunRobustnessSuite(const BenchConfig& config, Json* out) {
  std::cout << "\n== robustness: real truth under other camera paths, noise, "
               "missing ==\n";
  std::vector<MocapSequence> sources;
  std::string why;
  if (!LoadMocapSequences(config, &sources, &why)) {
    why += "; robustness suite skipped";
    std::cout << why << "\n";
    (*out)["skipped"] = why;
    return Status::OK();
  }
  // The default run: two sequences (the shortest with S + Rs and face) and
  // four cases.
  if (config.quick && config.mocap_sequences.empty()) {
    std::vector<MocapSequence> kept;
    for (MocapSequence& source : sources) {
      if (source.name == "yoga" || source.name == "face")
        kept.push_back(std::move(source));
    }
    if (!kept.empty()) sources = std::move(kept);
  }
  const std::vector<Case> cases = Cases(config.quick);
  struct Run {
    const MocapSequence* source = nullptr;
    const Case* test = nullptr;
    ReprojectedSequence sequence;
    Status made;
    RunOutcome outcome;
    double flat = 0.0;
  };
  std::vector<Run> runs;
  for (const MocapSequence& source : sources) {
    for (const Case& test : cases) {
      Run run;
      run.source = &source;
      run.test = &test;
      runs.push_back(std::move(run));
    }
  }
  ParallelFor(static_cast<int>(runs.size()), config.jobs, /*grain=*/1,
              [&](int begin, int end) {
                for (int i = begin; i < end; ++i) {
                  Run& run = runs[i];
                  run.made = GenerateReprojection(
                      run.source->truth, run.test->options, &run.sequence);
                  if (!run.made.ok()) continue;
                  run.flat = FlatFrobenius(run.sequence.truth);
                  ReconstructOptions options = DefaultReconstructOptions(
                      PublishedNumBases(run.source->name), config.threads);
                  options.solver.max_seconds = config.max_seconds;
                  run.outcome = ReconstructAndEvaluate(
                      options, run.sequence.measurements, run.sequence.truth);
                  run.outcome.model = Model();
                }
              });

  Table table({"sequence", "K", "case", "frob_z", "flat", "Lee et al.",
               "e3D (object)", "e3D cam", "rot err", "warn", "start", "iters",
               "conv", "total s"});
  Json results = Json::array();
  int above_flat = 0, scored = 0;
  for (const Run& run : runs) {
    const RunOutcome& o = run.outcome;
    const std::string name = run.source->name;
    const auto lee_sequence = LeeSlowRotation().find(name);
    double lee = -1.0;
    if (lee_sequence != LeeSlowRotation().end()) {
      const auto it = lee_sequence->second.find(run.test->name);
      if (it != lee_sequence->second.end()) lee = it->second;
    }
    const bool ok = run.made.ok() && o.ok;
    if (ok) {
      ++scored;
      if (o.errors.frob_zsign > run.flat) ++above_flat;
    }
    const bool warned = HasLittleRotationWarning(o);
    table.AddRow({name, std::to_string(PublishedNumBases(name)), run.test->name,
                  ok ? Fmt(o.errors.frob_zsign, 4) : "FAIL", Fmt(run.flat, 4),
                  lee < 0 ? "-" : Fmt(lee, 4), ok ? Fmt(o.errors.e3d, 4) : "-",
                  ok ? Fmt(o.errors.e3d_camera, 4) : "-",
                  ok && !std::isnan(o.errors.rotation_error)
                      ? Fmt(o.errors.rotation_error, 4)
                      : "-",
                  warned ? "yes" : "no", o.start, std::to_string(o.iterations),
                  o.converged ? "yes" : "no", Fmt(o.total_seconds, 1)});
    Json j;
    j["sequence"] = name;
    j["case"] = run.test->name;
    j["total_rotation_deg"] = run.test->options.total_rotation_deg;
    j["profile"] = SpeedProfileName(run.test->options.profile);
    j["noise_fraction"] = run.test->options.noise_fraction;
    j["missing_fraction"] = run.test->options.missing_fraction;
    j["num_bases"] = PublishedNumBases(name);
    j["ok"] = ok;
    if (!run.made.ok()) j["message"] = run.made.message();
    if (!o.message.empty()) j["message"] = o.message;
    AddMetrics(o.errors, &j);
    j["e3d_frame"] = EvaluationFrameName(o.errors.e3d_frame);
    j["flat_frob_zsign"] = run.flat;
    if (lee >= 0) j["lee_2016_frob_zsign"] = lee;
    j["little_rotation_warning"] = warned;
    j["start"] = o.start;
    j["iterations"] = o.iterations;
    j["converged"] = o.converged;
    j["total_seconds"] = o.total_seconds;
    results.push_back(j);
  }
  std::cout << table.ToString();
  std::cout << scored << " of " << runs.size() << " runs scored; " << above_flat
            << " above the flat answer (frob_z, camera frame)\n";
  if (config.max_seconds > 0) {
    std::cout << "(each refinement capped at " << config.max_seconds
              << " s wall time, --max_seconds)\n";
  }
  (*out)["runs"] = results;
  (*out)["above_flat"] = above_flat;
  (*out)["refine_max_seconds"] = config.max_seconds;
  return Status::OK();
}

namespace {

// e3D with one scale of the flat answer: each frame's centred image points
// with z = 0 (pixels; the scale aligns the units).
double FlatScaledE3D(const Measurements& m, const GroundTruth& truth) {
  std::vector<Eigen::Matrix3Xd> flat;
  for (int t = 0; t < m.num_frames; ++t) {
    Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Zero(3, m.num_points);
    x.topRows<2>() = m.W.middleRows(m.Row(t, 0), 2);
    flat.push_back(x);
  }
  return ComputeScaledE3D(truth.points_in_camera, flat);
}

struct PerspectiveRun {
  std::string name;
  int num_bases = 0;
  double distance_ratio = 0.0;  // 0: a real sequence
  Measurements measurements;
  GroundTruth truth;
  double flat = 0.0;
  RunOutcome outcome[2];  // weak perspective, perspective
  double scaled[2] = {-1.0, -1.0};
};

}  // namespace

Status RunPerspectiveSuite(const BenchConfig& config, Json* out) {
  std::cout << "\n== perspective: pinhole truth, weak-perspective and "
               "perspective cameras ==\n";
  std::vector<PerspectiveRun> runs;
  std::vector<MocapSequence> sources;
  std::string why;
  if (LoadMocapSequences(config, &sources, &why)) {
    for (const MocapSequence& source : sources) {
      if (!source.truth.HasObjectFrame()) continue;
      if (config.quick && source.name != "yoga") continue;
      for (const double ratio : {1.5, 3.0, 10.0, 30.0}) {
        ReprojectOptions options;
        options.distance_ratio = ratio;
        options.noise_fraction = 1e-3;
        ReprojectedSequence sequence;
        if (!GenerateReprojection(source.truth, options, &sequence).ok()) {
          continue;
        }
        PerspectiveRun run;
        run.name = source.name;
        run.num_bases = PublishedNumBases(source.name);
        run.distance_ratio = ratio;
        run.measurements = std::move(sequence.measurements);
        run.truth = std::move(sequence.truth);
        runs.push_back(std::move(run));
      }
    }
  } else {
    std::cout << why << "; pinhole re-projections skipped\n";
  }
  const std::filesystem::path folder =
      std::filesystem::path(config.datasets_dir) / "perspective";
  std::error_code error;
  if (!config.datasets_dir.empty() &&
      std::filesystem::is_directory(folder, error)) {
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
      if (entry.path().extension() == ".mat") files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    for (const std::filesystem::path& file : files) {
      PerspectiveRun run;
      run.name = file.stem().string();
      const Status read =
          ReadMeasurements(file.string(), InputOptions(), &run.measurements);
      const Status truth = ReadGroundTruth(file.string(), "X", &run.truth);
      if (!read.ok() || !truth.ok()) {
        std::cout << file.string() << " skipped: "
                  << (read.ok() ? truth.message() : read.message()) << "\n";
        continue;
      }
      for (int k = 1; k <= 3; ++k) {
        run.num_bases = k;
        runs.push_back(run);
      }
    }
  } else {
    std::cout << "no " << folder.string()
              << "; real perspective sequences skipped\n";
  }
  ParallelFor(
      static_cast<int>(runs.size()), config.jobs, /*grain=*/1,
      [&](int begin, int end) {
        for (int i = begin; i < end; ++i) {
          PerspectiveRun& run = runs[i];
          run.flat = FlatScaledE3D(run.measurements, run.truth);
          for (int camera = 0; camera < 2; ++camera) {
            ReconstructOptions options =
                DefaultReconstructOptions(run.num_bases, config.threads);
            options.solver.max_seconds = config.max_seconds;
            options.camera = camera == 0 ? CameraModel::kWeakPerspective
                                         : CameraModel::kPerspective;
            RunOutcome& o = run.outcome[camera];
            o = ReconstructAndEvaluate(options, run.measurements, run.truth);
            if (o.ok) {
              run.scaled[camera] = ComputeScaledE3D(run.truth.points_in_camera,
                                                    CameraFrameShapes(o.model));
            }
            o.model = Model();
          }
        }
      });
  Table table({"sequence", "ratio", "K", "flat", "weak persp.", "perspective",
               "persp./weak", "weak s", "persp. s"});
  Json results = Json::array();
  for (const PerspectiveRun& run : runs) {
    const auto score = [](double e) {
      return e < 0 ? std::string("FAIL") : Fmt(e, 4);
    };
    table.AddRow({run.name,
                  run.distance_ratio > 0 ? Fmt(run.distance_ratio, 1) : "real",
                  std::to_string(run.num_bases), Fmt(run.flat, 4),
                  score(run.scaled[0]), score(run.scaled[1]),
                  run.scaled[0] > 0 && run.scaled[1] >= 0
                      ? Fmt(run.scaled[1] / run.scaled[0], 2)
                      : "-",
                  Fmt(run.outcome[0].total_seconds, 1),
                  Fmt(run.outcome[1].total_seconds, 1)});
    Json j;
    j["sequence"] = run.name;
    j["distance_ratio"] = run.distance_ratio;
    j["num_bases"] = run.num_bases;
    j["flat_e3d_scaled"] = run.flat;
    j["weak_perspective_e3d_scaled"] = run.scaled[0];
    j["perspective_e3d_scaled"] = run.scaled[1];
    j["weak_perspective_seconds"] = run.outcome[0].total_seconds;
    j["perspective_seconds"] = run.outcome[1].total_seconds;
    if (!run.outcome[1].message.empty()) j["message"] = run.outcome[1].message;
    results.push_back(j);
  }
  std::cout << table.ToString();
  std::cout << "(e3D with one global scale, camera frame; ratio = camera "
               "distance / object size)\n";
  (*out)["runs"] = results;
  return Status::OK();
}

}  // namespace bench
}  // namespace nrsfm
