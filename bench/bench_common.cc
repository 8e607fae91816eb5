#include "bench/bench_common.h"

#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iomanip>
#include <sstream>
#include <thread>

#include <ceres/version.h>
#include <Eigen/Core>

#include "core/read_measurements.h"
#include "problems/extra_terms.h"

namespace nrsfm {
namespace bench {

int g_max_iterations = 0;

void SetDefaultMaxIterations(int max_iterations) {
  g_max_iterations = max_iterations;
}

ReconstructOptions DefaultReconstructOptions(int num_bases, int threads) {
  ReconstructOptions options;
  if (g_max_iterations > 0) options.solver.max_iterations = g_max_iterations;
  options.start.num_bases = num_bases;
  options.solver.num_threads = std::max(1, threads);
  return options;
}

bool EnableTwoCameraRigidity(ReconstructOptions* options) {
  options->priors = PriorMode::kManual;
  options->problem.term_weights[kRigidityTerm] = kTwoCameraRigidityWeight;
  return true;
}

Status Evaluate(const Model& model, const GroundTruth& truth, ShapeErrors* errors) {
  return EvaluateShapes(truth, ShapesOfModel(model, 0), errors);
}

RunOutcome ReconstructAndEvaluate(const ReconstructOptions& options,
                                  const Measurements& measurements,
                                  const GroundTruth& truth) {
  RunOutcome outcome;
  ReconstructResult result;
  const Status status = Reconstruct(options, measurements, &result);
  if (!status.ok()) {
    outcome.message = status.message();
    return outcome;
  }
  outcome.start = StartMethodName(result.start.method);
  outcome.init_seconds = result.start.seconds;
  outcome.refine_seconds = result.refine.seconds;
  outcome.total_seconds = result.total_seconds;
  outcome.iterations = result.refine.iterations;
  outcome.seconds_per_iteration =
      result.refine.iterations > 0
          ? (result.refine.minimizer_seconds - result.refine.callback_seconds) /
                result.refine.iterations
          : 0.0;
  outcome.reprojection_rms = result.refine.usable
                                 ? result.refine.reprojection_rms
                                 : result.start.reprojection_rms;
  outcome.linear_solver = result.refine.linear_solver;
  outcome.converged = result.refine.converged;
  outcome.warnings = result.start.warnings;
  outcome.warnings.insert(outcome.warnings.end(), result.warnings.begin(),
                          result.warnings.end());
  if (!result.refine.usable) {
    outcome.message = "refinement not usable: " + result.refine.message;
  }
  const Status eval = Evaluate(result.model, truth, &outcome.errors);
  if (!eval.ok()) {
    outcome.message = eval.message();
    return outcome;
  }
  outcome.ok = result.refine.usable;
  outcome.model = std::move(result.model);
  return outcome;
}

bool LoadMocapSequences(const BenchConfig& config, std::vector<MocapSequence>* sequences,
                        std::string* why) {
  namespace fs = std::filesystem;
  sequences->clear();
  std::error_code error;
  if (config.datasets_dir.empty() || !fs::is_directory(config.datasets_dir, error)) {
    *why = "no datasets directory '" + config.datasets_dir + "' (set --datasets_dir)";
    return false;
  }
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(config.datasets_dir, error)) {
    if (entry.path().extension() == ".mat") files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  for (const std::string& file : files) {
    MocapSequence sequence;
    sequence.name = fs::path(file).stem().string();
    if (!config.mocap_sequences.empty() &&
        ("," + config.mocap_sequences + ",").find("," + sequence.name + ",") ==
            std::string::npos) {
      continue;
    }
    Status status = ReadMeasurements(file, InputOptions(), &sequence.measurements);
    if (status.ok()) status = ReadGroundTruth(file, "", &sequence.truth);
    if (!status.ok()) {
      std::cout << "skip " << file << ": " << status.message() << "\n";
      continue;
    }
    sequences->push_back(std::move(sequence));
  }
  if (sequences->empty()) {
    *why = "no .mat with ground truth in " + config.datasets_dir;
    return false;
  }
  return true;
}

int PublishedNumBases(const std::string& name) {
  if (name == "drink" || name == "pickup") return 12;
  if (name == "yoga") return 10;
  if (name == "face") return 7;
  return 8;
}

void ParallelFor(int count, int jobs, const std::function<void(int)>& body) {
  if (jobs <= 1 || count <= 1) {
    for (int i = 0; i < count; ++i) body(i);
    return;
  }
  std::atomic<int> next{0};
  std::vector<std::thread> threads;
  for (int j = 0; j < std::min(jobs, count); ++j) {
    threads.emplace_back([&next, count, &body]() {
      for (int i; (i = next.fetch_add(1)) < count;) body(i);
    });
  }
  for (std::thread& thread : threads) thread.join();
}

SweepResult SweepK(
    const std::function<Status(std::uint64_t seed, SyntheticSequence*)>& make,
    const std::vector<int>& ks, int runs,
    const std::function<ReconstructOptions(int num_bases)>& options, int jobs) {
  SweepResult sweep;
  std::vector<SyntheticSequence> sequences(runs);
  std::vector<Status> made(runs);
  for (int r = 0; r < runs; ++r) {
    made[r] = make(static_cast<std::uint64_t>(r + 1), &sequences[r]);
  }
  // Outcome of K = ks[i], run r at index i * runs + r.
  std::vector<RunOutcome> outcomes(ks.size() * runs);
  ParallelFor(static_cast<int>(outcomes.size()), jobs, [&](int index) {
    const int k = ks[index / runs];
    const int r = index % runs;
    RunOutcome& o = outcomes[index];
    if (made[r].ok()) {
      o = ReconstructAndEvaluate(options(k), sequences[r].measurements,
                                 TruthShapes(sequences[r].truth));
      o.model = Model();  // not needed here; keeps the sweep's memory small
    } else {
      o.message = made[r].message();
    }
  });
  for (size_t i = 0; i < ks.size(); ++i) {
    const int k = ks[i];
    SweepPoint point;
    point.num_bases = k;
    std::vector<double> e3d_pct, z_pct, e3d, seconds;
    for (int r = 0; r < runs; ++r) {
      const RunOutcome& o = outcomes[i * runs + r];
      Json j;
      j["num_bases"] = k;
      j["seed"] = r + 1;
      j["ok"] = o.ok;
      if (!o.message.empty()) j["message"] = o.message;
      AddMetrics(o.errors, &j);
      j["reprojection_rms"] = o.reprojection_rms;
      j["start"] = o.start;
      j["iterations"] = o.iterations;
      j["total_seconds"] = o.total_seconds;
      sweep.runs.push_back(j);
      if (!o.ok) {
        ++point.failures;
        continue;
      }
      e3d_pct.push_back(o.errors.error3d_pct);
      z_pct.push_back(o.errors.zerror_pct);
      e3d.push_back(o.errors.e3d);
      seconds.push_back(o.total_seconds);
    }
    point.median_error3d_pct = Median(e3d_pct);
    point.median_zerror_pct = Median(z_pct);
    point.median_e3d = Median(e3d);
    point.median_seconds = Median(seconds);
    sweep.points.push_back(point);
  }
  return sweep;
}

GroundTruth TruthShapes(const Model& truth) {
  GroundTruth shapes;
  shapes.points_in_camera = CameraFrameShapes(truth, 0);
  shapes.source = "model";
  return shapes;
}

double Median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

std::string Fmt(double value, int precision) {
  if (std::isnan(value)) return "nan";
  std::ostringstream out;
  out << std::fixed << std::setprecision(precision) << value;
  return out.str();
}

Table::Table(std::vector<std::string> headers) : headers_(std::move(headers)) {}

void Table::AddRow(std::vector<std::string> cells) {
  cells.resize(headers_.size());
  rows_.push_back(std::move(cells));
}

std::string Table::ToString() const {
  std::vector<size_t> widths(headers_.size());
  for (size_t c = 0; c < headers_.size(); ++c) {
    widths[c] = headers_[c].size();
    for (const auto& row : rows_) widths[c] = std::max(widths[c], row[c].size());
  }
  std::ostringstream out;
  auto line = [&](const std::vector<std::string>& cells) {
    for (size_t c = 0; c < cells.size(); ++c) {
      out << (c == 0 ? "" : "  ") << std::setw(static_cast<int>(widths[c]))
          << cells[c];
    }
    out << "\n";
  };
  line(headers_);
  size_t total = 0;
  for (size_t w : widths) total += w + 2;
  out << std::string(total > 2 ? total - 2 : 0, '-') << "\n";
  for (const auto& row : rows_) line(row);
  return out.str();
}

namespace {

std::string ReadLink(const std::string& path) {
  std::error_code error;
  const auto target = std::filesystem::canonical(path, error);
  return error ? std::string("unknown") : target.string();
}

std::string CommandOutput(const std::string& command) {
  std::string output;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return output;
  char buffer[256];
  while (fgets(buffer, sizeof(buffer), pipe) != nullptr) output += buffer;
  pclose(pipe);
  while (!output.empty() && (output.back() == '\n' || output.back() == ' ')) {
    output.pop_back();
  }
  return output;
}

double StatusFieldMb(const char* field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  const std::string key = std::string(field) + ":";
  while (std::getline(status, line)) {
    if (line.rfind(key, 0) == 0) {
      return std::atof(line.c_str() + key.size()) / 1024.0;  // kB -> MB
    }
  }
  return std::nan("");
}

}  // namespace

Json ContextBlock(int threads) {
  Json context;
  const std::time_t now = std::time(nullptr);
  char date[64];
  std::strftime(date, sizeof(date), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  context["date"] = date;
  char host[256] = {0};
  gethostname(host, sizeof(host) - 1);
  context["hostname"] = host;
  context["nproc"] = std::thread::hardware_concurrency();
  context["threads"] = threads;
  std::string cpu = CommandOutput(
      "grep -m1 'model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2");
  if (!cpu.empty() && cpu[0] == ' ') cpu.erase(0, 1);
  context["cpu"] = cpu;
#if defined(__clang__)
  context["compiler"] = std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
  context["compiler"] = std::string("g++ ") + __VERSION__;
#else
  context["compiler"] = "unknown";
#endif
#ifdef NDEBUG
  context["build"] = "Release (NDEBUG)";
#else
  context["build"] = "assertions on (not Release)";
#endif
  context["ceres"] = CERES_VERSION_STRING;
  context["eigen"] = std::to_string(EIGEN_WORLD_VERSION) + "." +
                     std::to_string(EIGEN_MAJOR_VERSION) + "." +
                     std::to_string(EIGEN_MINOR_VERSION);
  context["blas"] = ReadLink("/etc/alternatives/libblas.so.3-x86_64-linux-gnu");
  context["lapack"] =
      ReadLink("/etc/alternatives/liblapack.so.3-x86_64-linux-gnu");
  context["ceres_sparse"] = CommandOutput(
      "grep -E '^#define CERES_(USE_EIGEN_SPARSE|NO_SUITESPARSE|USE_CXX_THREADS|"
      "USE_OPENMP)' /usr/include/ceres/internal/config.h 2>/dev/null | "
      "awk '{print $2}' | tr '\\n' ' '");
  return context;
}

void AddMetrics(const ShapeErrors& errors, Json* j) {
  for (const auto& [name, value] : MetricList(errors)) (*j)[name] = value;
}

std::string WritePlot(const BenchConfig& config, const PlotSpec& spec) {
  if (!config.plots) return "";
  static int gnuplot_state = -1;  // -1 unknown, 0 missing, 1 present
  if (gnuplot_state < 0) {
    gnuplot_state =
        std::system("command -v gnuplot > /dev/null 2>&1") == 0 ? 1 : 0;
    if (gnuplot_state == 0) {
      std::fprintf(stderr,
                   "note: gnuplot not found; plots skipped "
                   "(apt-get install gnuplot-nox)\n");
    }
  }
  if (gnuplot_state == 0) return "";
  namespace fs = std::filesystem;
  const fs::path dir(config.output_dir);
  const std::string data = (dir / (spec.name + ".dat")).string();
  const std::string script = (dir / (spec.name + ".gp")).string();
  const std::string image = (dir / (spec.name + ".svg")).string();
  {
    std::ofstream out(data);
    for (size_t s = 0; s < spec.series.size(); ++s) {
      out << "# " << spec.series[s].title << "\n";
      for (size_t i = 0; i < spec.series[s].x.size(); ++i) {
        out << spec.series[s].x[i] << " " << spec.series[s].y[i] << "\n";
      }
      out << "\n\n";
    }
  }
  {
    std::ofstream out(script);
    out << "set terminal svg size 720,480 dynamic enhanced font 'sans,12'\n"
        << "set output '" << image << "'\n"
        << "set title '" << spec.title << "' noenhanced\n"
        << "set xlabel '" << spec.xlabel << "' noenhanced\n"
        << "set ylabel '" << spec.ylabel << "' noenhanced\n"
        << "set grid\nset key top right noenhanced\n";
    if (spec.logx) out << "set logscale x\n";
    if (spec.logy) out << "set logscale y\n";
    out << "plot ";
    for (size_t s = 0; s < spec.series.size(); ++s) {
      out << (s == 0 ? "" : ", ") << "'" << data << "' index " << s
          << " using 1:2 with linespoints title '" << spec.series[s].title
          << "'";
    }
    out << "\n";
  }
  const std::string command = "gnuplot '" + script + "' > /dev/null 2>&1";
  if (std::system(command.c_str()) != 0) {
    std::fprintf(stderr, "note: gnuplot failed on %s; plot skipped\n",
                 script.c_str());
    return "";
  }
  return image;
}

ChildResult RunInChild(const std::function<Json()>& work) {
  ChildResult result;
  int fds[2];
  if (pipe(fds) != 0) {
    result.message = "pipe() failed";
    return result;
  }
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    result.message = "fork() failed";
    return result;
  }
  if (pid == 0) {
    close(fds[0]);
    Json out;
    out["start_rss_mb"] = StatusFieldMb("VmRSS");
    out["payload"] = work();
    out["peak_rss_mb"] = StatusFieldMb("VmHWM");
    const std::string text = out.dump();
    size_t written = 0;
    while (written < text.size()) {
      const ssize_t n = write(fds[1], text.data() + written,
                              text.size() - written);
      if (n <= 0) break;
      written += static_cast<size_t>(n);
    }
    close(fds[1]);
    _exit(0);
  }
  close(fds[1]);
  std::string text;
  char buffer[4096];
  ssize_t n;
  while ((n = read(fds[0], buffer, sizeof(buffer))) > 0) {
    text.append(buffer, static_cast<size_t>(n));
  }
  close(fds[0]);
  int wstatus = 0;
  waitpid(pid, &wstatus, 0);
  if (!WIFEXITED(wstatus) || WEXITSTATUS(wstatus) != 0 || text.empty()) {
    result.message = "child failed";
    return result;
  }
  const Json out = Json::parse(text, nullptr, false);
  if (out.is_discarded()) {
    result.message = "child sent bad JSON";
    return result;
  }
  result.ok = true;
  result.start_rss_mb = out.value("start_rss_mb", 0.0);
  result.peak_rss_mb = out.value("peak_rss_mb", 0.0);
  result.payload = out["payload"];
  return result;
}

double NowSeconds() {
  return std::chrono::duration<double>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

std::string WriteJson(const BenchConfig& config, const std::string& file,
                      const Json& json) {
  const std::string path =
      (std::filesystem::path(config.output_dir) / file).string();
  std::ofstream out(path);
  if (!out) {
    std::fprintf(stderr, "note: cannot write %s\n", path.c_str());
    return "";
  }
  out << json.dump(2) << "\n";
  return path;
}

}  // namespace bench
}  // namespace nrsfm
