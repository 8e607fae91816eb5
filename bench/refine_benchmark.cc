// nrsfm_solver_timing: the measurements behind the linear-solver rule
// (problems/linear_solver_choice.h) and the drink-sized timing of
// Reconstruct() (docs/performance.md).
//
//   --mode=table  every linear solver on random-basis data of each --sizes
//                 entry, all started from the same closed-form start;
//   --mode=drink  Reconstruct() with default options on synthetic
//                 (F, P, K) = (1102, 41, 12) data, the cost of one Jacobian
//                 (nrsfm_residual_benchmark compares it with autodiff), and
//                 on --drink (the real
//                 drink.mat) when given;
//   --mode=all    both.
// Prints plain-text tables to stdout. Not part of the test run. With every
// solver, large sizes such as (300, 5000, 5) take long (how long:
// docs/performance.md; --max_seconds is checked between iterations).
//   nrsfm_solver_timing --mode=table --sizes=1102x41x12,300x110x5
//   nrsfm_solver_timing --mode=drink --drink=../shared/datasets/drink.mat
#include <ceres/solver.h>
#include <gflags/gflags.h>
#include <glog/logging.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "core/eval/metrics.h"
#include "core/io/ground_truth.h"
#include "core/io/read_measurements.h"
#include "core/synthetic/synthetic.h"
#include "problems/linear_solver_choice.h"
#include "problems/problem_builder.h"
#include "solvers/pipeline/reconstruct.h"

DEFINE_string(mode, "all", "table | drink | all");
DEFINE_string(sizes, "1102x41x12,300x110x5,300x5000x5",
              "comma-separated FxPxK sizes of the solver table");
DEFINE_string(solvers,
              "dense_schur,sparse_schur,iterative_schur,sparse_normal_cholesky,"
              "cgnr",
              "comma-separated linear solvers of the table (auto allowed)");
DEFINE_int32(max_iterations, 100, "LM iterations at most per solve");
DEFINE_double(max_seconds, 60.0, "time limit of one solve in the table");
DEFINE_double(noise, 0.01, "std of the Gaussian noise on W (unit-cube shapes)");
DEFINE_int32(threads, 1, "Ceres threads");
DEFINE_int32(seed, 1, "seed of the synthetic data");
DEFINE_string(drink, "",
              "path of drink.mat for the real-data timing ('' = skip)");
DEFINE_int32(drink_bases, 12, "K for the drink-sized runs");

namespace nrsfm {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::vector<std::string> Split(const std::string& s, char separator) {
  std::vector<std::string> parts;
  std::stringstream stream(s);
  std::string part;
  while (std::getline(stream, part, separator)) {
    if (!part.empty()) parts.push_back(part);
  }
  return parts;
}

void Die(const Status& status) { LOG(FATAL) << status.message(); }

SyntheticSequence MakeSequence(int frames, int points, int bases) {
  RandomBasisOptions options;
  options.num_frames = frames;
  options.num_points = points;
  options.num_bases = bases;
  options.noise_stddev = FLAGS_noise;
  options.seed = FLAGS_seed;
  SyntheticSequence sequence;
  const Status status = GenerateRandomBasis(options, &sequence);
  if (!status.ok()) Die(status);
  return sequence;
}

double E3D(const SyntheticSequence& sequence, const Model& model) {
  return ComputeE3D(CameraFrameShapes(sequence.truth),
                    CameraFrameShapes(model));
}

// One Refine() with `choice` from `start`; prints one table row.
void SolveOnce(const SyntheticSequence& sequence, const Model& start,
               LinearSolverChoice choice) {
  Model model = start;
  SolverOptions options;
  options.linear_solver = choice;
  options.max_iterations = FLAGS_max_iterations;
  options.max_seconds = FLAGS_max_seconds;
  options.num_threads = FLAGS_threads;
  RefineSummary summary;
  const Status status = Refine(ProblemOptions(), options, sequence.measurements,
                               &model, &summary);
  const std::string name =
      LinearSolverName(choice) + (choice == LinearSolverChoice::kAuto
                                      ? "->" + summary.linear_solver
                                      : std::string());
  if (!status.ok()) {
    std::printf("  %-32s refused: %s\n", name.c_str(),
                status.message().c_str());
    std::fflush(stdout);
    return;
  }
  const int n = std::max(summary.iterations, 1);
  std::printf(
      "  %-32s %4d it %8.4f s/it (linear %8.4f, jacobian %7.4f) total %8.3f s"
      "  cost %.6e  rms %.4e  e3D %.4f  %s\n",
      name.c_str(), summary.iterations, summary.minimizer_seconds / n,
      summary.linear_solver_seconds / n, summary.jacobian_seconds / n,
      summary.seconds, summary.final_cost, summary.reprojection_rms,
      E3D(sequence, model), summary.message.substr(0, 40).c_str());
  std::fflush(stdout);
}

// The start Reconstruct()'s `auto` rule gives these measurements, not
// refined (0 LM iterations): the triple start for a video with 3K >= P/2,
// else of the factorization and rigid starts the lower initial cost.
Model StartKeptByAuto(int num_bases, const Measurements& measurements) {
  ReconstructOptions options;
  options.start.num_bases = num_bases;
  options.solver.max_iterations = 0;
  ReconstructResult result;
  const Status status = Reconstruct(options, measurements, &result);
  if (!status.ok()) Die(status);
  return result.model;
}

void SolverTable() {
  std::vector<LinearSolverChoice> solvers;
  for (const std::string& name : Split(FLAGS_solvers, ',')) {
    LinearSolverChoice choice;
    const Status status = ParseLinearSolver(name, &choice);
    if (!status.ok()) Die(status);
    solvers.push_back(choice);
  }
  for (const std::string& size : Split(FLAGS_sizes, ',')) {
    const std::vector<std::string> fpk = Split(size, 'x');
    CHECK_EQ(fpk.size(), 3u) << "bad --sizes entry " << size;
    const int frames = std::stoi(fpk[0]), points = std::stoi(fpk[1]),
              bases = std::stoi(fpk[2]);
    const SyntheticSequence sequence = MakeSequence(frames, points, bases);
    const Clock::time_point init_start = Clock::now();
    const Model start = StartKeptByAuto(bases, sequence.measurements);
    std::printf(
        "(F, P, K) = (%d, %d, %d), %d observations, noise %g; start in "
        "%.3f s: rms %.3e, e3D %.4f\n",
        frames, points, bases, sequence.measurements.NumVisible(), FLAGS_noise,
        SecondsSince(init_start), ReprojectionRms(sequence.measurements, start),
        E3D(sequence, start));
    std::fflush(stdout);
    for (LinearSolverChoice choice : solvers)
      SolveOnce(sequence, start, choice);
  }
}

// Seconds per Jacobian evaluation of the whole problem (average of 3).
double JacobianSeconds(const Measurements& measurements, const Model& start) {
  Model model = start;
  ProblemBuilder builder(&measurements, &model);
  Status status = builder.AddReprojectionTerms(ProblemOptions());
  if (!status.ok()) Die(status);
  ceres::Solver::Options options;
  options.max_num_iterations = 2;
  options.num_threads = FLAGS_threads;
  options.logging_type = ceres::SILENT;
  LinearSolverChoice used;
  status = ConfigureLinearSolver(LinearSolverChoice::kAuto, &builder, &options,
                                 &used);
  if (!status.ok()) Die(status);
  ceres::Solver::Summary summary;
  ceres::Solve(options, builder.problem(), &summary);
  return summary.jacobian_evaluation_time_in_seconds /
         summary.num_jacobian_evaluations;
}

void PrintReconstruct(const std::string& label,
                      const Measurements& measurements,
                      const ReconstructResult& result) {
  const RefineSummary& r = result.refine;
  std::printf(
      "%s: %d observations, total %.3f s = init %.3f s (%s, rms %.3e) + refine "
      "%.3f s\n"
      "  refine: %s, %d iterations, %.4f s/iteration, usable %d, rms %.3e -> "
      "%.3e, cost %.6e -> %.6e\n"
      "  refine time: build %.3f, preprocess %.3f, residuals %.3f, jacobians "
      "%.3f, linear solver %.3f, minimizer %.3f s\n  %s\n",
      label.c_str(), measurements.NumVisible(), result.total_seconds,
      result.start.seconds, StartMethodName(result.start.method),
      result.start.reprojection_rms, r.seconds, r.linear_solver.c_str(),
      r.iterations, r.iterations > 0 ? r.minimizer_seconds / r.iterations : 0.0,
      r.usable, r.initial_reprojection_rms, r.reprojection_rms, r.initial_cost,
      r.final_cost, r.build_seconds, r.preprocessor_seconds, r.residual_seconds,
      r.jacobian_seconds, r.linear_solver_seconds, r.minimizer_seconds,
      r.message.c_str());
  std::fflush(stdout);
}

void DrinkTiming() {
  const int bases = FLAGS_drink_bases;
  const SyntheticSequence sequence = MakeSequence(1102, 41, bases);
  ReconstructOptions options;
  options.start.num_bases = bases;
  options.solver.num_threads = FLAGS_threads;
  options.solver.max_iterations = FLAGS_max_iterations;
  ReconstructResult result;
  Status status = Reconstruct(options, sequence.measurements, &result);
  if (!status.ok()) Die(status);
  PrintReconstruct("synthetic (1102, 41, " + std::to_string(bases) + ")",
                   sequence.measurements, result);
  std::printf("  refined e3D %.4f\n", E3D(sequence, result.model));
  std::printf("  one Jacobian: %.4f s\n",
              JacobianSeconds(sequence.measurements, result.model));
  std::fflush(stdout);

  if (FLAGS_drink.empty()) return;
  Measurements drink;
  status = ReadMeasurements(FLAGS_drink, InputOptions(), &drink);
  if (!status.ok()) Die(status);
  status = Reconstruct(options, drink, &result);
  if (!status.ok()) Die(status);
  PrintReconstruct(FLAGS_drink + " (K = " + std::to_string(bases) + ")", drink,
                   result);
  GroundTruth truth;
  if (ReadGroundTruth(FLAGS_drink, "", &truth).ok()) {
    const Model start = StartKeptByAuto(bases, drink);
    std::printf(
        "  e3D vs the file's truth (%s): start %.4f, refined %.4f\n",
        truth.source.c_str(),
        ComputeE3D(truth.points_in_camera, CameraFrameShapes(start)),
        ComputeE3D(truth.points_in_camera, CameraFrameShapes(result.model)));
  }
  std::fflush(stdout);
}

}  // namespace
}  // namespace nrsfm

int main(int argc, char** argv) {
  FLAGS_logtostderr = true;
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  google::InitGoogleLogging(argv[0]);
  if (FLAGS_mode == "table" || FLAGS_mode == "all") nrsfm::SolverTable();
  if (FLAGS_mode == "drink" || FLAGS_mode == "all") nrsfm::DrinkTiming();
  return 0;
}
