#include "solvers/refine/structured_solver.h"

#include <ceres/solver.h>
#include <glog/logging.h>

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>

#include "solvers/refine/band_preconditioner.h"
#include "solvers/refine/conjugate_gradients.h"
#include "solvers/refine/schur_elimination.h"
#include "solvers/refine/structured_jacobian.h"
#include "solvers/refine/structured_layout.h"

namespace nrsfm {
namespace {

using Clock = std::chrono::steady_clock;
using structured::Block;
using structured::StructuredBlocks;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The constants of Ceres' Levenberg–Marquardt, from its own option defaults
// (ceres::Solver::Options), so that both minimisers use the same ones.
struct LevenbergMarquardtConstants {
  double min_diagonal, max_diagonal;  // D's clamp
  double min_relative_decrease;       // a step is taken above this quality
  double max_radius, min_radius;      // the solve ends below min_radius
};

const LevenbergMarquardtConstants& CeresConstants() {
  static const LevenbergMarquardtConstants constants = [] {
    const ceres::Solver::Options ceres_defaults;
    return LevenbergMarquardtConstants{ceres_defaults.min_lm_diagonal,
                                       ceres_defaults.max_lm_diagonal,
                                       ceres_defaults.min_relative_decrease,
                                       ceres_defaults.max_trust_region_radius,
                                       ceres_defaults.min_trust_region_radius};
  }();
  return constants;
}

// The radius update of Ceres' LevenbergMarquardtStrategy (not options
// there): after a taken step of quality ρ the radius grows by
// 1 / max(kMinRadiusShrink, 1 − (2ρ − 1)³); after a rejected one it is
// divided by a factor that starts at kInitialDecrease and doubles with each
// rejection in a row.
constexpr double kMinRadiusShrink = 1.0 / 3.0;
constexpr double kInitialDecrease = 2.0;

// The Levenberg–Marquardt loop: Ceres' step (JᵀJ + μD) δ = −Jᵀr, D =
// diag(JᵀJ) clamped to [min_diagonal, max_diagonal], μ = 1/radius, and its
// trust-region update of the radius.
class Solver {
 public:
  Solver(const StructuredSolverOptions& options, const StructuredBlocks& blocks)
      : options_(options),
        blocks_(blocks),
        jacobian_(blocks, options.solver.num_threads),
        schur_(blocks, jacobian_, options.solver.num_threads),
        preconditioner_(blocks, jacobian_, options.solver.num_threads) {}

  bool Run(StructuredSolverSummary* summary);

 private:
  bool Evaluate(bool with_jacobian, double* cost);
  // g = Jᵀr, D and J_pᵀ J_p from the Jacobian of the last Evaluate(true).
  void ComputeGradientAndScaling();
  // The step for μ; returns the conjugate-gradient iterations.
  int SolveStep(double mu, Eigen::VectorXd* step_reduced,
                Eigen::VectorXd* step_eliminated);
  std::vector<double> Save() const;
  void Restore(const std::vector<double>& saved);
  void Step(const std::vector<double>& saved, const Eigen::VectorXd& reduced,
            const Eigen::VectorXd& eliminated);
  double ParameterNorm() const;

  const StructuredSolverOptions& options_;
  const StructuredBlocks& blocks_;
  structured::StructuredJacobian jacobian_;
  structured::SchurElimination schur_;
  structured::BandPreconditioner preconditioner_;
  Eigen::VectorXd gradient_reduced_, gradient_eliminated_, d_reduced_,
      d_eliminated_;
  double evaluate_seconds_ = 0.0, preconditioner_seconds_ = 0.0,
         cg_seconds_ = 0.0;
};

bool Solver::Evaluate(bool with_jacobian, double* cost) {
  const Clock::time_point start = Clock::now();
  const bool ok = jacobian_.Evaluate(with_jacobian, cost);
  evaluate_seconds_ += SecondsSince(start);
  return ok;
}

void Solver::ComputeGradientAndScaling() {
  schur_.ComputeGram();
  jacobian_.Gradient(&gradient_reduced_, &gradient_eliminated_);
  jacobian_.ColumnSquaredNorms(&d_reduced_, &d_eliminated_);
  schur_.AddGridColumnSquaredNorms(&d_reduced_, &d_eliminated_);
  const LevenbergMarquardtConstants& lm = CeresConstants();
  d_reduced_ = d_reduced_.cwiseMax(lm.min_diagonal).cwiseMin(lm.max_diagonal);
  d_eliminated_ =
      d_eliminated_.cwiseMax(lm.min_diagonal).cwiseMin(lm.max_diagonal);
}

int Solver::SolveStep(double mu, Eigen::VectorXd* step_reduced,
                      Eigen::VectorXd* step_eliminated) {
  schur_.Factor(mu, d_eliminated_);
  Clock::time_point start = Clock::now();
  preconditioner_.Build(mu, d_reduced_, schur_.grid_grams());
  preconditioner_seconds_ += SecondsSince(start);
  start = Clock::now();
  Eigen::VectorXd rhs;
  schur_.ReducedRightHandSide(gradient_reduced_, gradient_eliminated_, &rhs);
  structured::ConjugateGradientsOptions cg;
  cg.relative_tolerance = options_.solver.cg_relative_tolerance;
  cg.max_iterations = options_.solver.max_cg_iterations;
  const int iterations = structured::ConjugateGradients(
      cg,
      [&](const Eigen::VectorXd& v, Eigen::VectorXd* out) {
        schur_.ApplyReduced(v, mu, d_reduced_, out);
      },
      [&](const Eigen::VectorXd& v, Eigen::VectorXd* out) {
        preconditioner_.Apply(v, out);
      },
      rhs, step_reduced);
  schur_.BackSubstitute(*step_reduced, gradient_eliminated_, step_eliminated);
  cg_seconds_ += SecondsSince(start);
  return iterations;
}

std::vector<double> Solver::Save() const {
  std::vector<double> saved;
  for (const Block& b : blocks_.blocks) {
    saved.insert(saved.end(), b.values, b.values + b.ambient);
  }
  return saved;
}

void Solver::Restore(const std::vector<double>& saved) {
  std::size_t k = 0;
  for (const Block& b : blocks_.blocks) {
    std::copy(saved.begin() + k, saved.begin() + k + b.ambient, b.values);
    k += b.ambient;
  }
}

void Solver::Step(const std::vector<double>& saved,
                  const Eigen::VectorXd& reduced,
                  const Eigen::VectorXd& eliminated) {
  std::size_t k = 0;
  for (const Block& b : blocks_.blocks) {
    const double* delta =
        (b.eliminated ? eliminated : reduced).data() + b.offset;
    if (b.manifold != nullptr) {
      b.manifold->Plus(saved.data() + k, delta, b.values);
    } else {
      for (int i = 0; i < b.ambient; ++i) b.values[i] = saved[k + i] + delta[i];
    }
    k += b.ambient;
  }
}

double Solver::ParameterNorm() const {
  double sum = 0.0;
  for (const Block& b : blocks_.blocks) {
    sum += Eigen::Map<const Eigen::VectorXd>(b.values, b.ambient).squaredNorm();
  }
  return std::sqrt(sum);
}

bool Solver::Run(StructuredSolverSummary* summary) {
  const Clock::time_point start = Clock::now();
  const SolverOptions& solver = options_.solver;
  double cost = 0.0;
  if (!Evaluate(true, &cost)) {
    summary->message = "the cost is not finite at the start";
    return true;
  }
  summary->initial_cost = cost;
  if (solver.progress)
    solver.progress(IterationReport{0, cost, SecondsSince(start)});
  ComputeGradientAndScaling();
  const LevenbergMarquardtConstants& lm = CeresConstants();
  double radius = solver.initial_trust_region_radius,
         decrease = kInitialDecrease;
  int iteration = 0;
  summary->message = "iteration limit";
  Eigen::VectorXd step_reduced, step_eliminated;
  while (true) {
    const double gradient_max = std::max(
        gradient_reduced_.size() ? gradient_reduced_.cwiseAbs().maxCoeff()
                                 : 0.0,
        gradient_eliminated_.size() ? gradient_eliminated_.cwiseAbs().maxCoeff()
                                    : 0.0);
    if (gradient_max <= solver.gradient_tolerance) {
      summary->message = "gradient tolerance";
      summary->converged = true;
      break;
    }
    if (iteration >= solver.max_iterations) break;
    if (solver.max_seconds > 0.0 && SecondsSince(start) >= solver.max_seconds) {
      summary->message = "time limit";
      break;
    }
    if (solver.stop_requested && solver.stop_requested()) {
      summary->message = "stopped on request";
      summary->stopped = true;
      break;
    }
    ++iteration;
    const double mu = 1.0 / radius;
    summary->cg_iterations += SolveStep(mu, &step_reduced, &step_eliminated);
    // The decrease the linear model predicts: cost − ½||r + J δ||².
    double j_dot_r = 0.0, j_squared = 0.0;
    jacobian_.StepProducts(step_reduced, step_eliminated, &j_dot_r, &j_squared);
    const double model_decrease = -(j_dot_r + 0.5 * j_squared);
    const std::vector<double> saved = Save();
    const double step_norm =
        std::sqrt(step_reduced.squaredNorm() + step_eliminated.squaredNorm());
    if (step_norm <= solver.parameter_tolerance *
                         (ParameterNorm() + solver.parameter_tolerance)) {
      summary->message = "parameter tolerance";
      summary->converged = true;
      break;
    }
    Step(saved, step_reduced, step_eliminated);
    // With the Jacobian: most steps are taken, and a rejected one evaluates
    // again at the restored values (the same bits as before the step).
    double new_cost = 0.0;
    const bool finite = Evaluate(true, &new_cost);
    const double ratio = finite && model_decrease > 0.0
                             ? (cost - new_cost) / model_decrease
                             : -1.0;
    VLOG(3) << "structured LM " << iteration << ": cost " << cost << " -> "
            << new_cost << " ratio " << ratio << " radius " << radius
            << " step " << step_norm;
    if (ratio > lm.min_relative_decrease) {
      const double change = cost - new_cost;
      cost = new_cost;
      radius =
          std::min(lm.max_radius,
                   radius / std::max(kMinRadiusShrink,
                                     1.0 - std::pow(2.0 * ratio - 1.0, 3)));
      decrease = kInitialDecrease;
      ComputeGradientAndScaling();
      if (solver.progress)
        solver.progress(IterationReport{iteration, cost, SecondsSince(start)});
      if (change <= solver.function_tolerance * cost) {
        summary->message = "function tolerance";
        summary->converged = true;
        break;
      }
    } else {
      Restore(saved);
      double restored_cost = 0.0;
      Evaluate(true, &restored_cost);
      radius /= decrease;
      decrease *= 2.0;
      if (solver.progress)
        solver.progress(IterationReport{iteration, cost, SecondsSince(start)});
      if (radius < lm.min_radius) {
        summary->message = "trust region below its minimum";
        break;
      }
    }
  }
  summary->usable = std::isfinite(cost);
  summary->iterations = iteration;
  summary->final_cost = cost;
  summary->evaluate_seconds = evaluate_seconds_;
  summary->preconditioner_seconds = preconditioner_seconds_;
  summary->cg_seconds = cg_seconds_;
  summary->total_seconds = SecondsSince(start);
  return true;
}

}  // namespace

bool SolveStructured(const StructuredSolverOptions& options,
                     const StructuredLayout& layout, ceres::Problem* problem,
                     StructuredSolverSummary* summary, std::string* error) {
  StructuredBlocks blocks;
  return SolveStructured(options, layout, problem, summary, error, &blocks);
}

bool SolveStructured(const StructuredSolverOptions& options,
                     const StructuredLayout& layout, ceres::Problem* problem,
                     StructuredSolverSummary* summary, std::string* error,
                     StructuredBlocks* kept) {
  CHECK(kept != nullptr);
  *summary = StructuredSolverSummary();
  const Clock::time_point start = Clock::now();
  StructuredBlocks& blocks = *kept;
  if (blocks.residuals.empty() &&
      !structured::LayOutBlocks(layout, problem, &blocks, error)) {
    blocks = StructuredBlocks();
    return false;
  }
  VLOG(2) << "structured layout in " << SecondsSince(start)
          << " s: " << blocks.residuals.size() << " residual blocks, "
          << blocks.grids.size() << " grids (terms summed at once), "
          << blocks.coupling_residuals.size()
          << " other blocks that couple points";
  Solver solver(options, blocks);
  const double setup_seconds = SecondsSince(start);
  VLOG(2) << "structured solver set up in " << setup_seconds << " s";
  const bool ran = solver.Run(summary);
  summary->setup_seconds = setup_seconds;
  return ran;
}

}  // namespace nrsfm
