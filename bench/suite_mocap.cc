// mocap suite: every .mat of config.datasets_dir that holds ground truth
// (drink, pickup, yoga: S + Rs; face: P3_gt), reconstructed at the K of the
// published BMM numbers (drink 12, pickup 12, yoga 10, face 7; other files 8)
// with each reconstruction strategy, then (with --full) a K sweep. Scored by
// the field's protocol (core/eval/metrics.h, docs/metrics.md): e3D in the
// object frame against the world S when the truth has S + Rs, in the camera
// frame otherwise; also the camera-frame e3D, the z-sign Frobenius error and
// the rotation error against Rs, with the time of each stage.
#include <algorithm>
#include <cmath>
#include <cstdio>
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
#include "core/io/ground_truth.h"
#include "core/io/read_measurements.h"
#include "core/math/parallel_for.h"
#include "problems/extra_terms.h"
#include "solvers/pipeline/prior_rule.h"

namespace nrsfm {
namespace bench {
namespace {

// Published e3D in the same protocol (object frame for S + Rs truth),
// -1 = not published: PTA (Akhter et al. 2011), BMM (Dai et al. 2012),
// R-BMM (Kumar, WACV 2020), and the best we know of (Kumar & Van Gool,
// ECCV 2022).
struct PublishedNumbers {
  double pta, bmm, rbmm, best;
};

const std::map<std::string, PublishedNumbers>& Published() {
  static const std::map<std::string, PublishedNumbers> table = {
      {"drink", {0.0250, 0.0266, 0.0119, 0.0071}},
      {"pickup", {0.2369, 0.1731, 0.0198, 0.0152}},
      {"yoga", {0.1625, 0.1150, 0.0129, 0.0122}},
      {"face", {-1, 0.0303, 0.0179, 0.0145}},
  };
  return table;
}

using Sequence = MocapSequence;

// Strategies: "default" (Reconstruct() with default options: the prior rule
// of solvers/pipeline/prior_rule.h chooses start and terms), "plain" (no extra
// term, the factorization/rigid start rule: the pipeline before the rule), or
// '+'-joined parts with manual terms: "triple" (the corrective-triple start,
// solvers/start/triple_start.h) and "ts" (the object-frame temporal shape
// prior, λ_S = kTemporalShapeWeight, problems/temporal_error.h). "all" runs the
// ablation list below.
const double kTemporalShapeWeight = PriorRuleOptions().temporal_shape_weight;

std::vector<std::string> Strategies(const BenchConfig& config) {
  if (config.strategy == "all") {
    return {"default", "plain", "triple", "triple+ts"};
  }
  return {config.strategy};
}

bool HasPart(const std::string& strategy, const std::string& part) {
  std::string padded = "+" + strategy + "+";
  return padded.find("+" + part + "+") != std::string::npos;
}

RunOutcome RunStrategy(const std::string& strategy, int num_bases,
                       const BenchConfig& config, const Sequence& sequence) {
  ReconstructOptions options =
      DefaultReconstructOptions(num_bases, config.threads);
  options.solver.max_seconds = config.max_seconds;
  if (strategy != "default") options.priors = PriorMode::kManual;
  if (HasPart(strategy, "triple")) options.start.method = StartMethod::kTriple;
  if (HasPart(strategy, "ts"))
    options.problem.term_weights[kTemporalShapeTerm] = kTemporalShapeWeight;
  return ReconstructAndEvaluate(options, sequence.measurements, sequence.truth);
}

Json OutcomeJson(const RunOutcome& o) {
  Json j;
  j["ok"] = o.ok;
  if (!o.message.empty()) j["message"] = o.message;
  AddMetrics(o.errors, &j);
  j["e3d_frame"] = EvaluationFrameName(o.errors.e3d_frame);
  j["reprojection_rms"] = o.reprojection_rms;
  j["start"] = o.start;
  j["iterations"] = o.iterations;
  j["init_seconds"] = o.init_seconds;
  j["refine_seconds"] = o.refine_seconds;
  j["total_seconds"] = o.total_seconds;
  j["linear_solver"] = o.linear_solver;
  return j;
}

}  // namespace

Status RunMocapSuite(const BenchConfig& config, Json* out) {
  std::cout << "\n== mocap: real motion-capture sequences ==\n";
  std::vector<Sequence> sequences;
  std::string why;
  if (!LoadMocapSequences(config, &sequences, &why)) {
    why += "; mocap suite skipped";
    std::cout << why << "\n";
    (*out)["skipped"] = why;
    return Status::OK();
  }

  Table table({"sequence",  "F",       "P",       "K",        "strategy",
               "e3D",       "frame",   "PTA",     "BMM",      "R-BMM",
               "best pub.", "e3D cam", "rot err", "frob_z",   "rms",
               "start",     "iters",   "init s",  "refine s", "total s"});
  Json runs = Json::array();
  // Every (sequence, strategy) run, --jobs at a time, reported in order.
  const std::vector<std::string> strategies = Strategies(config);
  std::vector<RunOutcome> outcomes(sequences.size() * strategies.size());
  ParallelFor(static_cast<int>(outcomes.size()), config.jobs, /*grain=*/1,
              [&](int begin, int end) {
                for (int i = begin; i < end; ++i) {
                  const Sequence& sequence = sequences[i / strategies.size()];
                  outcomes[i] = RunStrategy(strategies[i % strategies.size()],
                                            PublishedNumBases(sequence.name),
                                            config, sequence);
                  outcomes[i].model = Model();
                }
              });
  int index = 0;
  for (const Sequence& sequence : sequences) {
    const auto published = Published().find(sequence.name);
    const int num_bases = PublishedNumBases(sequence.name);
    for (const std::string& strategy : strategies) {
      const RunOutcome& o = outcomes[index++];
      const auto pub = [&](double PublishedNumbers::*field) -> std::string {
        if (published == Published().end()) return "-";
        const double value = published->second.*field;
        return value < 0 ? "-" : Fmt(value, 4);
      };
      table.AddRow({sequence.name,
                    std::to_string(sequence.measurements.num_frames),
                    std::to_string(sequence.measurements.num_points),
                    std::to_string(num_bases),
                    strategy,
                    o.ok ? Fmt(o.errors.e3d, 4) : "FAIL",
                    EvaluationFrameName(o.errors.e3d_frame),
                    pub(&PublishedNumbers::pta),
                    pub(&PublishedNumbers::bmm),
                    pub(&PublishedNumbers::rbmm),
                    pub(&PublishedNumbers::best),
                    Fmt(o.errors.e3d_camera, 4),
                    std::isnan(o.errors.rotation_error)
                        ? "-"
                        : Fmt(o.errors.rotation_error, 4),
                    Fmt(o.errors.frob_zsign, 4),
                    Fmt(o.reprojection_rms, 4),
                    o.start,
                    std::to_string(o.iterations),
                    Fmt(o.init_seconds, 2),
                    Fmt(o.refine_seconds, 2),
                    Fmt(o.total_seconds, 2)});
      Json j = OutcomeJson(o);
      j["sequence"] = sequence.name;
      j["num_bases"] = num_bases;
      j["strategy"] = strategy;
      if (published != Published().end()) {
        j["best_published_e3d"] = published->second.best;
      }
      runs.push_back(j);
      std::cout << "  " << sequence.name << " K=" << num_bases << " "
                << strategy << ": e3D " << Fmt(o.errors.e3d, 4) << " ("
                << Fmt(o.total_seconds, 2) << " s)"
                << (o.message.empty() ? "" : " " + o.message) << std::endl;
    }
  }
  std::cout << table.ToString();
  if (config.max_seconds > 0) {
    std::cout << "(each refinement capped at " << config.max_seconds
              << " s wall time, --max_seconds; 0 removes the cap)\n";
  }
  if (config.jobs > 1) {
    std::cout << "(" << config.jobs << " runs at a time, --jobs: times include "
              << "sharing the machine)\n";
  }
  (*out)["refine_max_seconds"] = config.max_seconds;
  (*out)["jobs"] = config.jobs;
  (*out)["runs"] = runs;

  if (!config.full) return Status::OK();
  // K sweep (plain strategy and the first listed one).
  const std::vector<int> sweep = {1, 2, 3, 4, 5, 6, 8, 10, 12};
  PlotSpec plot;
  plot.name = "mocap_e3d_vs_k";
  plot.title = "mocap: e3D vs K (" + Strategies(config).front() + ")";
  plot.xlabel = "K";
  plot.ylabel = "e3D";
  Table sweep_table({"sequence", "K", "e3D", "frob_z", "rms", "total s"});
  Json sweep_runs = Json::array();
  for (const Sequence& sequence : sequences) {
    PlotSeries series;
    series.title = sequence.name;
    for (int k : sweep) {
      if (3 * k + 1 > sequence.measurements.num_points) continue;
      const RunOutcome o =
          RunStrategy(Strategies(config).front(), k, config, sequence);
      sweep_table.AddRow({sequence.name, std::to_string(k),
                          o.ok ? Fmt(o.errors.e3d, 4) : "FAIL",
                          Fmt(o.errors.frob_zsign, 4),
                          Fmt(o.reprojection_rms, 4), Fmt(o.total_seconds, 2)});
      Json j = OutcomeJson(o);
      j["sequence"] = sequence.name;
      j["num_bases"] = k;
      sweep_runs.push_back(j);
      if (o.ok) {
        series.x.push_back(k);
        series.y.push_back(o.errors.e3d);
      }
    }
    plot.series.push_back(series);
  }
  std::cout << "\nK sweep:\n" << sweep_table.ToString();
  (*out)["k_sweep"] = sweep_runs;
  const std::string path = WritePlot(config, plot);
  if (!path.empty()) (*out)["plots"].push_back(path);
  return Status::OK();
}

}  // namespace bench
}  // namespace nrsfm
