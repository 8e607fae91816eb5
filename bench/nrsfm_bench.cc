// nrsfm_bench: the benchmark suites (docs/benchmark.md). With no flags it runs
// the reduced default (a few minutes on 2 cores, --jobs=2): paper-random with R
// = 1, superquadric, shoe at K = 4 (monocular and two cameras), mocap at the
// published K, robustness on yoga and face (four cases) and perspective on
// yoga and the perspective/ sequences when
// ../shared/datasets exists, and a small scale sweep.
//
//   --suite=default|paper-random|superquadric|shoe|mocap|robustness|perspective|uncertainty|scale|all
//   --full            paper-sized runs (R = 30, full K ranges, K sweeps)
//   --runs=R          random runs per setting (overrides the suite default)
//   --datasets_dir    folder of the mocap .mat files
//   --output_dir      results.json and plots (default ./bench_results)
//   --threads         Ceres threads
//   --plots           write plots (gnuplot, SVG); skipped with a note if absent
//   --mocap_sequences comma-separated .mat stems (default: every file)
//   --max_seconds     wall-time cap of each shoe, mocap, robustness and
//                     scale refinement (default run: 30; one suite alone or
//                     --full: none)
//   --jobs            reconstructions run at once (default 2)
//   --max_iterations  LM iterations per refinement (default: the library's)
//   --strategy        mocap: default | plain | triple, ts joined by '+' | all
//
// Output: tables on stdout; <output_dir>/results.json with a "context" block
// (date, machine, threads, versions, BLAS) and one object per suite.
#include <gflags/gflags.h>
#include <glog/logging.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_config.h"
#include "bench/context.h"
#include "bench/measure.h"
#include "bench/report.h"
#include "bench/suites.h"

DEFINE_string(suite, "default",
              "default | paper-random | superquadric | shoe | mocap | "
              "robustness | perspective | scale | all");
DEFINE_bool(full, false, "paper-sized runs (R = 30, full K ranges, K sweeps)");
DEFINE_int32(runs, 0, "random runs per setting (0 = the suite's default)");
DEFINE_string(datasets_dir, "../shared/datasets",
              "folder with the mocap .mat files (skipped when absent)");
DEFINE_string(output_dir, "./bench_results", "where results.json and plots go");
DEFINE_int32(threads, 1, "Ceres threads per reconstruction");
DEFINE_bool(plots, true, "write plots with gnuplot (SVG)");
DEFINE_string(mocap_sequences, "",
              "comma-separated .mat stems the mocap suite runs ('' = all)");
DEFINE_double(max_seconds, 30.0,
              "wall-time cap of each shoe, mocap, robustness and scale "
              "refinement in seconds in the default run (0 = none); one suite "
              "alone (--suite=shoe, mocap, ...) or --full runs uncapped unless "
              "this flag is given");
DEFINE_int32(jobs, 2,
             "reconstructions run at once (paper-random, superquadric, shoe, "
             "mocap; the scale suite always runs one at a time)");
DEFINE_int32(max_iterations, 0,
             "LM iterations per refinement (0 = the library default)");
DEFINE_string(strategy, "default",
              "mocap strategy: default (the library's defaults), plain (no "
              "extra term, factorization/rigid starts), or '+'-joined triple "
              "(corrective-triple start) and ts (temporal shape prior), or all "
              "(the ablation)");

namespace {

using nrsfm::Status;
using nrsfm::bench::BenchConfig;
using nrsfm::bench::Json;

struct Suite {
  const char* name;
  Status (*run)(const BenchConfig&, Json*);
};

const std::vector<Suite>& AllSuites() {
  static const std::vector<Suite> suites = {
      {"paper-random", nrsfm::bench::RunPaperRandomSuite},
      {"superquadric", nrsfm::bench::RunSuperquadricSuite},
      {"shoe", nrsfm::bench::RunShoeSuite},
      {"mocap", nrsfm::bench::RunMocapSuite},
      {"robustness", nrsfm::bench::RunRobustnessSuite},
      {"perspective", nrsfm::bench::RunPerspectiveSuite},
      {"uncertainty", nrsfm::bench::RunUncertaintySuite},
      {"scale", nrsfm::bench::RunScaleSuite},
  };
  return suites;
}

}  // namespace

int main(int argc, char** argv) {
  FLAGS_logtostderr = true;
  gflags::SetUsageMessage("nrsfm benchmark suites (see bench/nrsfm_bench.cc)");
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  google::InitGoogleLogging(argv[0]);

  BenchConfig config;
  config.full = FLAGS_full || FLAGS_suite == "all";
  config.runs = FLAGS_runs;
  config.datasets_dir = FLAGS_datasets_dir;
  config.output_dir = FLAGS_output_dir;
  config.threads = FLAGS_threads;
  config.plots = FLAGS_plots;
  config.strategy = FLAGS_strategy;
  config.mocap_sequences = FLAGS_mocap_sequences;
  config.quick = FLAGS_suite == "default" && !FLAGS_full;
  config.max_seconds = FLAGS_max_seconds;
  if (!config.quick &&
      gflags::GetCommandLineFlagInfoOrDie("max_seconds").is_default) {
    config.max_seconds = 0.0;
  }
  config.jobs = FLAGS_jobs;
  nrsfm::bench::SetDefaultMaxIterations(FLAGS_max_iterations);
  {
    std::ostringstream bad;
    if (FLAGS_runs < 0)
      bad << "--runs must be >= 0, got " << FLAGS_runs;
    else if (FLAGS_threads < 1)
      bad << "--threads must be >= 1, got " << FLAGS_threads;
    else if (FLAGS_jobs < 1)
      bad << "--jobs must be >= 1, got " << FLAGS_jobs;
    else if (!(FLAGS_max_seconds >= 0))
      bad << "--max_seconds must be >= 0, got " << FLAGS_max_seconds;
    if (!bad.str().empty()) {
      std::cerr << "error: " << bad.str() << "\n";
      return 2;
    }
  }
  bool strategy_ok = FLAGS_strategy == "plain" || FLAGS_strategy == "all" ||
                     FLAGS_strategy == "default";
  if (!strategy_ok && !FLAGS_strategy.empty()) {
    strategy_ok = true;
    std::string rest = FLAGS_strategy + "+";
    for (size_t pos; (pos = rest.find('+')) != std::string::npos;) {
      const std::string part = rest.substr(0, pos);
      strategy_ok &= part == "triple" || part == "ts";
      rest.erase(0, pos + 1);
    }
  }
  if (!strategy_ok) {
    std::cerr << "error: unknown --strategy '" << FLAGS_strategy << "'\n";
    return 2;
  }

  std::vector<Suite> selected;
  if (FLAGS_suite == "default" || FLAGS_suite == "all") {
    selected = AllSuites();
  } else {
    for (const Suite& suite : AllSuites()) {
      if (FLAGS_suite == suite.name) selected.push_back(suite);
    }
  }
  if (selected.empty()) {
    std::cerr << "error: unknown --suite '" << FLAGS_suite
              << "' (default | paper-random | superquadric | shoe | mocap | "
                 "robustness | scale | all)\n";
    return 2;
  }
  std::error_code error;
  std::filesystem::create_directories(config.output_dir, error);
  if (error) {
    std::cerr << "error: cannot create --output_dir '" << config.output_dir
              << "': " << error.message() << "\n";
    return 2;
  }

  Json results;
  results["context"] = nrsfm::bench::ContextBlock(config.threads);
  results["context"]["suite"] = FLAGS_suite;
  results["context"]["full"] = config.full;
  results["context"]["strategy"] = config.strategy;
  std::cout << "nrsfm_bench: suite " << FLAGS_suite
            << (config.full ? " (full)" : " (reduced; --full for paper size)")
            << ", " << config.threads << " thread(s), output "
            << config.output_dir << "\n";
  int failures = 0;
  const double start = nrsfm::bench::NowSeconds();
  for (const Suite& suite : selected) {
    Json out;
    const double suite_start = nrsfm::bench::NowSeconds();
    const Status status = suite.run(config, &out);
    out["seconds"] = nrsfm::bench::NowSeconds() - suite_start;
    if (!status.ok()) {
      std::cout << "suite " << suite.name << " FAILED: " << status.message()
                << "\n";
      out["error"] = status.message();
      ++failures;
    }
    results["suites"][suite.name] = out;
    std::cout << std::flush;
    // Written after every suite so a long run leaves partial results.
    nrsfm::bench::WriteJson(config, "results.json", results);
  }
  results["context"]["total_seconds"] = nrsfm::bench::NowSeconds() - start;
  const std::string path =
      nrsfm::bench::WriteJson(config, "results.json", results);
  std::cout << "\nresults: " << (path.empty() ? "(not written)" : path) << " ("
            << nrsfm::bench::Fmt(nrsfm::bench::NowSeconds() - start, 1)
            << " s)\n";
  return failures == 0 ? 0 : 1;
}
