#include "solvers/refine/solver_options.h"

#include <glog/logging.h>

#include <algorithm>
#include <string>
#include <thread>

#include "core/model/enum_names.h"
#include "core/model/option_checker.h"

namespace nrsfm {

namespace {

constexpr EnumName<MinimizerOption> kMinimizerNames[] = {
    {MinimizerOption::kAuto, "auto"},
    {MinimizerOption::kStructured, "structured"},
    {MinimizerOption::kCeres, "ceres"},
};

}  // namespace

Status ParseMinimizer(const std::string& name, MinimizerOption* option) {
  return ParseName(kMinimizerNames, name, "minimizer", option);
}

const char* MinimizerName(MinimizerOption option) {
  return NameOf(kMinimizerNames, option);
}

int DefaultNumThreads() {
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

Status SolverOptions::Check() const {
  OptionChecker check("solver options");
  check.AtLeast("max_iterations", max_iterations, 0);
  check.AtLeast("function_tolerance", function_tolerance, 0.0);
  check.AtLeast("gradient_tolerance", gradient_tolerance, 0.0);
  check.AtLeast("parameter_tolerance", parameter_tolerance, 0.0);
  check.AtLeast("max_seconds", max_seconds, 0.0);
  check.AtLeast("num_threads", num_threads, 1);
  check.FinitePositive("initial_trust_region_radius",
                       initial_trust_region_radius);
  check.AtLeast("verbosity", verbosity, 0);
  check.Require(cg_relative_tolerance > 0.0 && cg_relative_tolerance < 1.0,
                "cg_relative_tolerance must be in (0, 1), got " +
                    std::to_string(cg_relative_tolerance));
  check.AtLeast("max_cg_iterations", max_cg_iterations, 1);
  check.Require(minimizer != MinimizerOption::kStructured ||
                    linear_solver == LinearSolverChoice::kAuto ||
                    linear_solver == LinearSolverChoice::kStructured,
                std::string("linear_solver = ") +
                    LinearSolverName(linear_solver) +
                    " is one of Ceres' linear solvers: it applies with "
                    "minimizer = ceres, not structured");
  check.Require(minimizer != MinimizerOption::kCeres ||
                    linear_solver != LinearSolverChoice::kStructured,
                "linear_solver = structured is the structured minimizer: "
                "with minimizer = ceres name one of Ceres' linear solvers "
                "or auto");
  return check.status();
}

ceres::Solver::Options ToCeresOptions(const SolverOptions& options) {
  ceres::Solver::Options ceres_options;
  ceres_options.max_num_iterations = options.max_iterations;
  ceres_options.function_tolerance = options.function_tolerance;
  ceres_options.gradient_tolerance = options.gradient_tolerance;
  ceres_options.parameter_tolerance = options.parameter_tolerance;
  if (options.max_seconds > 0.0) {
    ceres_options.max_solver_time_in_seconds = options.max_seconds;
  }
  ceres_options.num_threads = options.num_threads;
  ceres_options.initial_trust_region_radius =
      options.initial_trust_region_radius;
  ceres_options.logging_type = ceres::SILENT;
  ceres_options.minimizer_progress_to_stdout = false;
  return ceres_options;
}

Status SolveCeres(
    const SolverOptions& options,
    const std::function<Status(ceres::Solver::Options*)>& configure,
    ceres::Problem* problem, ceres::Solver::Summary* summary) {
  CHECK(problem != nullptr && summary != nullptr);
  ceres::Solver::Options ceres_options = ToCeresOptions(options);
  NRSFM_RETURN_IF_ERROR(configure(&ceres_options));
  std::string invalid;
  if (!ceres_options.IsValid(&invalid)) {
    return Status::Error("invalid Ceres options: " + invalid);
  }
  ceres::Solve(ceres_options, problem, summary);
  return Status::OK();
}

}  // namespace nrsfm
