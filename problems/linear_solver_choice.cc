#include "problems/linear_solver_choice.h"

#include <ceres/ordered_groups.h>

#include <algorithm>
#include <memory>
#include <sstream>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "core/model/enum_names.h"

namespace nrsfm {
namespace {

constexpr EnumName<LinearSolverChoice> kLinearSolverNames[] = {
    {LinearSolverChoice::kAuto, "auto"},
    {LinearSolverChoice::kDenseSchur, "dense_schur"},
    {LinearSolverChoice::kSparseSchur, "sparse_schur"},
    {LinearSolverChoice::kIterativeSchur, "iterative_schur"},
    {LinearSolverChoice::kSparseNormalCholesky, "sparse_normal_cholesky"},
    {LinearSolverChoice::kCgnr, "cgnr"},
    {LinearSolverChoice::kDenseQr, "dense_qr"},
    {LinearSolverChoice::kStructured, "structured"},
};

bool IsSchur(LinearSolverChoice choice) {
  return choice == LinearSolverChoice::kDenseSchur ||
         choice == LinearSolverChoice::kSparseSchur ||
         choice == LinearSolverChoice::kIterativeSchur;
}

std::string Gigabytes(double bytes) {
  std::ostringstream s;
  s.precision(3);
  s << bytes / 1e9 << " GB";
  return s.str();
}

}  // namespace

Status ParseLinearSolver(const std::string& name, LinearSolverChoice* choice) {
  return ParseName(kLinearSolverNames, name, "linear solver", choice);
}

const char* LinearSolverName(LinearSolverChoice choice) {
  return NameOf(kLinearSolverNames, choice);
}

ProblemStructure DescribePointBlocks(ProblemBuilder* builder) {
  ceres::Problem& problem = *builder->problem();
  ProblemStructure s;
  s.points_are_independent = builder->PointBlocksAreIndependent();
  for (double* block : builder->PointBlocks()) {
    if (problem.IsParameterBlockConstant(block)) continue;
    ++s.num_point_blocks;
    s.num_point_parameters += problem.ParameterBlockSize(block);
  }
  return s;
}

ProblemStructure DescribeProblem(ProblemBuilder* builder) {
  ceres::Problem& problem = *builder->problem();
  ProblemStructure s = DescribePointBlocks(builder);
  s.num_residuals = problem.NumResiduals();

  std::unordered_set<const double*> free_points;
  for (double* block : builder->PointBlocks()) {
    if (!problem.IsParameterBlockConstant(block)) free_points.insert(block);
  }
  for (double* block : builder->NonPointBlocks()) {
    if (!problem.IsParameterBlockConstant(block)) {
      s.num_other_parameters += problem.ParameterBlockSize(block);
    }
  }

  // Entries of the reduced (Schur) matrix when the points are eliminated:
  // at most Σ_p n_p², n_p = free non-point parameters sharing a residual
  // with point p, and at most (all free non-point parameters)².
  std::unordered_map<const double*, std::unordered_set<const double*>> touching;
  std::vector<ceres::ResidualBlockId> residual_blocks;
  problem.GetResidualBlocks(&residual_blocks);
  std::vector<double*> blocks;
  for (ceres::ResidualBlockId id : residual_blocks) {
    problem.GetParameterBlocksForResidualBlock(id, &blocks);
    for (const double* point : blocks) {
      if (free_points.count(point) == 0) continue;
      for (double* other : blocks) {
        if (free_points.count(other) == 0 &&
            !problem.IsParameterBlockConstant(other)) {
          touching[point].insert(other);
        }
      }
    }
  }
  double sum_squares = 0.0;
  for (const auto& [point, others] : touching) {
    double n = 0.0;
    for (const double* other : others) {
      n += problem.ParameterBlockSize(const_cast<double*>(other));
    }
    sum_squares += n * n;
  }
  const double all = s.num_other_parameters;
  s.schur_matrix_entries = std::min(sum_squares, all * all);

  // The frame of every free per-frame block, then the widest span in time of
  // one residual block.
  const Model& model = *builder->model();
  std::unordered_map<const double*, int> frame_of;
  for (int t = 0; t < model.num_frames; ++t) {
    frame_of[builder->WeightsBlock(t)] = t;
    for (int c = 0; c < model.num_cameras; ++c) {
      frame_of[builder->RotationBlock(t, c)] = t;
      frame_of[builder->TranslationBlock(t, c)] = t;
      if (c > 0) frame_of[builder->ScaleBlock(t, c)] = t;
    }
  }
  for (ceres::ResidualBlockId id : residual_blocks) {
    problem.GetParameterBlocksForResidualBlock(id, &blocks);
    int first = model.num_frames, last = -1;
    for (double* block : blocks) {
      const auto it = frame_of.find(block);
      if (it == frame_of.end() || problem.IsParameterBlockConstant(block))
        continue;
      first = std::min(first, it->second);
      last = std::max(last, it->second);
    }
    if (last >= first)
      s.frame_coupling = std::max(s.frame_coupling, last - first);
  }
  return s;
}

LinearSolverChoice ChooseLinearSolver(const ProblemStructure& structure) {
  if (structure.num_point_blocks == 0) {
    return LinearSolverChoice::kSparseNormalCholesky;
  }
  return LinearSolverChoice::kStructured;
}

Status ConfigureLinearSolver(LinearSolverChoice choice, ProblemBuilder* builder,
                             ceres::Solver::Options* options,
                             LinearSolverChoice* used) {
  const ProblemStructure s = DescribeProblem(builder);
  if (choice == LinearSolverChoice::kAuto) choice = ChooseLinearSolver(s);
  *used = choice;
  if (choice == LinearSolverChoice::kStructured) {
    return Status::Error(
        "linear solver structured: not a Ceres linear solver (SolveProblem "
        "runs it)");
  }
  const std::string name = LinearSolverName(choice);
  const bool eliminate_points =
      IsSchur(choice) && s.points_are_independent && s.num_point_blocks > 0;
  const double total = s.num_point_parameters + s.num_other_parameters;

  double dense_bytes = 0.0;
  if (choice == LinearSolverChoice::kDenseQr) {
    dense_bytes = 8.0 * s.num_residuals * total;
  } else if (choice == LinearSolverChoice::kDenseSchur) {
    const double reduced = eliminate_points ? s.num_other_parameters : total;
    dense_bytes = 8.0 * reduced * reduced;
  } else if (choice == LinearSolverChoice::kSparseSchur && eliminate_points) {
    dense_bytes = 8.0 * s.schur_matrix_entries;
  }
  if (dense_bytes > kMaxDenseBytes) {
    return Status::Error(
        "linear solver " + name + ": the " +
        (choice == LinearSolverChoice::kDenseQr ? "dense Jacobian"
                                                : "reduced (Schur) matrix") +
        " would take " + Gigabytes(dense_bytes) + " (limit " +
        Gigabytes(kMaxDenseBytes) +
        "); use auto, iterative_schur or cgnr for a problem this size");
  }

  switch (choice) {
    case LinearSolverChoice::kDenseSchur:
      options->linear_solver_type = ceres::DENSE_SCHUR;
      options->num_threads = 1;  // see the header
      break;
    case LinearSolverChoice::kSparseSchur:
      options->linear_solver_type = ceres::SPARSE_SCHUR;
      options->num_threads = 1;
      break;
    case LinearSolverChoice::kIterativeSchur:
      options->linear_solver_type = ceres::ITERATIVE_SCHUR;
      // Not SCHUR_JACOBI: Ceres 2.1 builds it by visiting every pair of
      // blocks that share a point, ~(3F)² per point when every frame sees
      // every point (docs/performance.md).
      options->preconditioner_type = ceres::JACOBI;
      break;
    case LinearSolverChoice::kSparseNormalCholesky:
      options->linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
      break;
    case LinearSolverChoice::kCgnr:
      options->linear_solver_type = ceres::CGNR;
      options->preconditioner_type = ceres::JACOBI;
      break;
    case LinearSolverChoice::kDenseQr:
      options->linear_solver_type = ceres::DENSE_QR;
      break;
    case LinearSolverChoice::kAuto:
    case LinearSolverChoice::kStructured:
      LOG(FATAL) << "unreachable";
  }

  // An explicit ordering for every solver: Ceres orders the blocks of one
  // group by address, which would make the column order (and the rounding)
  // depend on the heap layout. Groups by kind keep runs bitwise repeatable.
  options->linear_solver_ordering.reset();
  if (IsSchur(choice) && !eliminate_points) {
    return Status::OK();  // Ceres picks an independent set to eliminate.
  }
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  int group = 0;
  const std::vector<double*> points = builder->PointBlocks();
  if (eliminate_points) {
    for (double* block : points) ordering->AddElementToGroup(block, group);
    ++group;
  }
  for (const std::vector<double*>& blocks : builder->NonPointBlockGroups()) {
    for (double* block : blocks) ordering->AddElementToGroup(block, group);
    ++group;
  }
  if (!eliminate_points) {
    for (double* block : points) ordering->AddElementToGroup(block, group);
  }
  options->linear_solver_ordering = ordering;
  return Status::OK();
}

}  // namespace nrsfm
