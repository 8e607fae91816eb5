// The oracle of the structured solver's linear algebra: Ceres' own Jacobian
// of a problem (ceres::Problem::Evaluate, tangent-space columns) as a dense
// matrix whose columns are in a StructuredBlocks' order, the reduced
// columns (each block at its offset) then the eliminated ones; and two small
// problems laid out as Refine() lays them out.
#ifndef NRSFM_TESTS_SOLVERS_REFINE_DENSE_ORACLE_H_
#define NRSFM_TESTS_SOLVERS_REFINE_DENSE_ORACLE_H_

#include <ceres/problem.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/synthetic/synthetic.h"
#include "problems/extra_terms.h"
#include "problems/problem_builder.h"
#include "solvers/refine/refine.h"
#include "solvers/refine/schur_elimination.h"
#include "solvers/refine/structured_jacobian.h"
#include "solvers/refine/structured_layout.h"

namespace nrsfm {

struct DenseJacobian {
  Eigen::MatrixXd jacobian;  // rows: residuals; columns: [reduced, eliminated]
  Eigen::VectorXd residuals;
  double cost = 0.0;
};

// Evaluates `problem` (whose free blocks `blocks` lays out).
inline DenseJacobian EvaluateDense(const structured::StructuredBlocks& blocks,
                                   ceres::Problem* problem) {
  std::vector<std::pair<int, int>> order;  // (column, block index)
  for (std::size_t i = 0; i < blocks.blocks.size(); ++i) {
    const structured::Block& b = blocks.blocks[i];
    order.push_back({(b.eliminated ? blocks.num_reduced : 0) + b.offset,
                     static_cast<int>(i)});
  }
  std::sort(order.begin(), order.end());
  ceres::Problem::EvaluateOptions evaluate;
  for (const auto& [column, i] : order) {
    evaluate.parameter_blocks.push_back(blocks.blocks[i].values);
  }
  DenseJacobian dense;
  std::vector<double> residuals;
  ceres::CRSMatrix crs;
  EXPECT_TRUE(
      problem->Evaluate(evaluate, &dense.cost, &residuals, nullptr, &crs));
  EXPECT_EQ(crs.num_cols, blocks.num_reduced + blocks.num_eliminated);
  dense.jacobian = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row) {
    for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k) {
      dense.jacobian(row, crs.cols[k]) = crs.values[k];
    }
  }
  dense.residuals =
      Eigen::Map<const Eigen::VectorXd>(residuals.data(), residuals.size());
  return dense;
}

// D = diag(JᵀJ) as the structured solver forms it (its column norms plus
// the grids' part), before its clamping; `schur` after ComputeGram().
inline void ColumnScaling(const structured::StructuredJacobian& jacobian,
                          const structured::SchurElimination& schur,
                          Eigen::VectorXd* d_reduced,
                          Eigen::VectorXd* d_eliminated) {
  jacobian.ColumnSquaredNorms(d_reduced, d_eliminated);
  schur.AddGridColumnSquaredNorms(d_reduced, d_eliminated);
}

// A problem at perturbed values of a synthetic sequence's truth, its
// builder and its blocks (MakeStructuredLayout); held by pointer, as the
// builder points into it.
struct OracleProblem {
  SyntheticSequence sequence;
  Model model;
  std::unique_ptr<ProblemBuilder> builder;
  structured::StructuredBlocks blocks;
};

enum class OracleCase {
  // Two cameras of the shoe (self-occlusion: the reprojection panel with
  // missing entries), the rigidity term (the rig blocks shared by every
  // frame: the border and corner) and rotation acceleration (band 2).
  kTwoCamerasRig,
  // A smooth superquadric with 20 % missing entries and the terms of
  // bilinear form as grids (temporal shape, smoothness, deformation), the
  // smoothness coupling points (C̃ one sparse factor), temporal and
  // rotation acceleration.
  kCoupledPointsAndGrids,
};

inline std::unique_ptr<OracleProblem> MakeOracleProblem(OracleCase which) {
  auto p = std::make_unique<OracleProblem>();
  ProblemOptions terms;
  if (which == OracleCase::kTwoCamerasRig) {
    ShoeOptions shoe;
    shoe.num_frames = 12;
    shoe.num_points = 30;
    shoe.noise_stddev = 0.01;
    EXPECT_TRUE(GenerateShoe(shoe, &p->sequence).ok());
    terms.term_weights[kRigidityTerm] = 1.0;
    terms.term_weights[kRotationAccelerationTerm] = 2.0;
  } else {
    SuperquadricOptions superquadric;
    superquadric.num_frames = 15;
    superquadric.num_points = 20;
    superquadric.noise_stddev = 0.005;
    superquadric.missing_fraction = 0.2;
    superquadric.seed = 3;
    EXPECT_TRUE(GenerateSuperquadric(superquadric, &p->sequence).ok());
    terms.term_weights[kTemporalShapeTerm] = 0.5;
    terms.term_weights[kRotationAccelerationTerm] = 10.0;
    terms.term_weights[kTemporalTerm] = 0.1;
    terms.term_weights[kSmoothnessTerm] = 0.05;
    terms.term_weights[kDeformationTerm] = 0.3;
  }
  p->model = p->sequence.truth;
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 0.05);
  for (Eigen::Index i = 0; i < p->model.rotations.size(); ++i)
    p->model.rotations.data()[i] += normal(rng);
  for (Eigen::Index i = 0; i < p->model.basis.size(); ++i)
    p->model.basis.data()[i] += normal(rng);
  p->builder =
      std::make_unique<ProblemBuilder>(&p->sequence.measurements, &p->model);
  EXPECT_TRUE(p->builder->AddReprojectionTerms(terms).ok());
  EXPECT_TRUE(AddExtraTerms(terms, p->builder.get()).ok());
  std::string error;
  EXPECT_TRUE(structured::LayOutBlocks(MakeStructuredLayout(p->builder.get()),
                                       p->builder->problem(), &p->blocks,
                                       &error))
      << error;
  return p;
}

// The cases' names in a parameterised test.
inline std::string OracleCaseName(
    const testing::TestParamInfo<OracleCase>& info) {
  return info.param == OracleCase::kTwoCamerasRig ? "TwoCamerasRig"
                                                  : "CoupledPointsAndGrids";
}

inline const auto kOracleCases = testing::Values(
    OracleCase::kTwoCamerasRig, OracleCase::kCoupledPointsAndGrids);

}  // namespace nrsfm

#endif  // NRSFM_TESTS_SOLVERS_REFINE_DENSE_ORACLE_H_
