// Shared pieces of the nrsfm_bench suites (bench/suite_*.cc): the run
// configuration, one reconstruction + evaluation against ground truth,
// statistics, the stdout table, the JSON context block, plots (gnuplot) and
// peak-memory measurement in a forked child.
#ifndef NRSFM_BENCH_BENCH_COMMON_H_
#define NRSFM_BENCH_BENCH_COMMON_H_

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "core/measurements.h"
#include "core/metrics.h"
#include "core/model.h"
#include "core/status.h"
#include "core/synthetic.h"
#include "solvers/reconstruct.h"

namespace nrsfm {
namespace bench {

using Json = nlohmann::ordered_json;

// What every suite reads (from the gflags of bench/nrsfm_bench.cc).
struct BenchConfig {
  bool full = false;          // the paper-sized run (e.g. R = 30) instead of the reduced default
  bool quick = false;         // the default run of every suite (--suite=default): smaller still
  int runs = 0;               // R, random runs per setting; 0 = the suite's default
  std::string datasets_dir;   // folder with the mocap .mat files ("" = none)
  std::string output_dir;     // JSON and plots go here
  int threads = 1;            // Ceres threads
  bool plots = true;          // write plots when gnuplot is available
  std::string mocap_sequences;  // comma-separated file stems to run ("" = all)
  double max_seconds = 0;     // wall-time cap of each shoe and mocap refinement, 0 = none
  int jobs = 1;               // reconstructions run at once (the scale suite: always 1)
  std::string strategy = "default";  // mocap: default | plain | triple, ts joined by '+' | all
};

// The options every suite uses unless it says otherwise: Reconstruct()'s
// defaults with K and the thread count set.
// (--max_iterations > 0 replaces the LM iteration limit; set once by main
// through SetDefaultMaxIterations.)
ReconstructOptions DefaultReconstructOptions(int num_bases, int threads);
void SetDefaultMaxIterations(int max_iterations);

// The one place that decides how "second camera + rigidity" runs: the
// multi-camera rigidity term (problems/rigidity_error.h) with
// weight kTwoCameraRigidityWeight, the value of the CLI's two-camera shoe
// test (tests/tools/cli_test.cc, ExtraTermFlags). Returns true (the shoe
// table's column header says whether the term ran).
constexpr double kTwoCameraRigidityWeight = 100.0;
bool EnableTwoCameraRigidity(ReconstructOptions* options);

// One reconstruction scored against camera-0 ground truth.
struct RunOutcome {
  bool ok = false;              // Reconstruct() succeeded and the refinement is usable
  std::string message;          // why not
  ShapeErrors errors;           // core/metrics.h
  std::string start;            // StartMethodName of the start kept
  double init_seconds = 0;
  double refine_seconds = 0;
  double total_seconds = 0;
  int iterations = 0;           // LM iterations
  // The solver's own minimizer time / iterations: without the time in the
  // callbacks, where auto's two starts wait for each other.
  double seconds_per_iteration = 0;
  double reprojection_rms = 0;  // refined, input units
  std::string linear_solver;
  bool converged = false;       // the refinement ended by a tolerance
  std::vector<std::string> warnings;  // the start's and the result's
  Model model;                  // the reconstruction
};

// Scores `model` (camera 0) against `truth` (core/metrics.h EvaluateShapes:
// the object frame when the truth has one).
Status Evaluate(const Model& model, const GroundTruth& truth, ShapeErrors* errors);

// Reconstruct() + Evaluate(). Never fails: problems go into outcome.message.
RunOutcome ReconstructAndEvaluate(const ReconstructOptions& options,
                                  const Measurements& measurements,
                                  const GroundTruth& truth);

// K sweep on synthetic data: for each K and each run r = 0 … runs − 1,
// make(seed = r + 1) generates a sequence, options(K) reconstructs it, and
// the errors against its truth are collected. Medians over the runs (failed
// runs excluded and counted).
struct SweepPoint {
  int num_bases = 0;
  int failures = 0;
  double median_error3d_pct = 0, median_zerror_pct = 0, median_e3d = 0;
  double median_seconds = 0;
};
struct SweepResult {
  std::vector<SweepPoint> points;
  Json runs = Json::array();  // every run
};
// The (K, run) reconstructions run `jobs` at a time; results are collected
// in order, so the output does not depend on `jobs` (the times do: runs
// that share the machine take longer).
SweepResult SweepK(
    const std::function<Status(std::uint64_t seed, SyntheticSequence*)>& make,
    const std::vector<int>& ks, int runs,
    const std::function<ReconstructOptions(int num_bases)>& options, int jobs);

// Calls body(0) … body(count − 1) on min(jobs, count) threads (jobs ≤ 1: in
// order on this thread). Each call must write only its own outputs.
void ParallelFor(int count, int jobs, const std::function<void(int)>& body);

// A real sequence with ground truth (the mocap and robustness suites).
struct MocapSequence {
  std::string name;  // file stem
  Measurements measurements;
  GroundTruth truth;
};
// Every .mat of config.datasets_dir with measurements and ground truth,
// sorted by name, restricted to config.mocap_sequences when given. Files
// that cannot be read are skipped with a line on stdout. Returns false with
// `why` when there is no such folder or no such file.
bool LoadMocapSequences(const BenchConfig& config, std::vector<MocapSequence>* sequences,
                        std::string* why);
// K of the published numbers for a sequence (drink 12, pickup 12, yoga 10,
// face 7; 8 for any other).
int PublishedNumBases(const std::string& name);

// Camera-0 ground truth of a synthetic model (ShapeInCamera(t, 0)).
GroundTruth TruthShapes(const Model& truth);

double Median(std::vector<double> values);  // NaN when empty

// Fixed-precision number ("nan" for NaN).
std::string Fmt(double value, int precision = 3);

// A plain-text table with right-aligned columns.
class Table {
 public:
  explicit Table(std::vector<std::string> headers);
  void AddRow(std::vector<std::string> cells);
  std::string ToString() const;

 private:
  std::vector<std::string> headers_;
  std::vector<std::vector<std::string>> rows_;
};

// Date, host, cores, threads, compiler, Ceres/Eigen versions, BLAS/LAPACK.
Json ContextBlock(int threads);

// Sets (*j)[name] = value for every metric of `errors` (MetricList,
// core/metrics.h: the names result.json and `nrsfm evaluate` use).
void AddMetrics(const ShapeErrors& errors, Json* j);

// A line plot: one curve per series. Written as <output_dir>/<name>.svg
// (gnuplot, svg terminal) with its data in <name>.dat and script in <name>.gp.
struct PlotSeries {
  std::string title;
  std::vector<double> x, y;
};
struct PlotSpec {
  std::string name;   // file stem
  std::string title;
  std::string xlabel, ylabel;
  bool logx = false, logy = false;
  std::vector<PlotSeries> series;
};
// Returns the path of the plot, or "" with a one-line note on stderr when
// plots are off or gnuplot is missing or fails (never an error).
std::string WritePlot(const BenchConfig& config, const PlotSpec& spec);

// Runs `work` in a forked child and measures its memory. The child's peak
// resident set (VmHWM) starts at the RSS it inherits, so both are reported.
// `work` returns a JSON object that is passed back through a pipe.
struct ChildResult {
  bool ok = false;
  std::string message;
  double start_rss_mb = 0;  // RSS when the child started (inherited pages)
  double peak_rss_mb = 0;   // VmHWM at the end of the child
  Json payload;
};
ChildResult RunInChild(const std::function<Json()>& work);

// Seconds since an arbitrary epoch (steady clock).
double NowSeconds();

// Writes `json` to <output_dir>/<file>; returns the path or "" on failure
// (with a note on stderr).
std::string WriteJson(const BenchConfig& config, const std::string& file,
                      const Json& json);

}  // namespace bench
}  // namespace nrsfm

#endif  // NRSFM_BENCH_BENCH_COMMON_H_
