#include "problems/extra_terms.h"

#include <glog/logging.h>

#include <cmath>
#include <memory>
#include <vector>

#include "problems/deformation_error.h"
#include "problems/delaunay_edges.h"
#include "problems/rigidity_error.h"
#include "problems/smoothness_error.h"
#include "problems/temporal_error.h"

namespace nrsfm {
namespace {

// One function per term: adds its residual blocks with weight λ > 0
// (docs/problem.md has each residual).

Status AddSmoothness(double weight, const ProblemOptions& options,
                     ProblemBuilder* builder, int* num_blocks) {
  std::vector<SmoothnessStencil> stencils;
  NRSFM_RETURN_IF_ERROR(ComputeSmoothnessStencils(
      builder->measurements(), options.smoothness_edges, &stencils));
  const Model& model = *builder->model();
  // λ / F: the frames' sum is an average (problems/smoothness_error.h).
  const double scale = std::sqrt(weight / model.num_frames);
  for (const SmoothnessStencil& stencil : stencils) {
    std::vector<double> coefficients = {1.0};
    std::vector<double*> blocks = {nullptr, builder->BasisBlock(stencil.point)};
    for (std::size_t q = 0; q < stencil.neighbours.size(); ++q) {
      coefficients.push_back(-stencil.weights[q]);
      blocks.push_back(builder->BasisBlock(stencil.neighbours[q]));
    }
    // One cost function for the stencil's blocks in every frame.
    ceres::CostFunction* cost = builder->Own(std::make_unique<SmoothnessError>(
        model.num_bases, scale, std::move(coefficients)));
    for (int t = 0; t < model.num_frames; ++t) {
      blocks[0] = builder->WeightsBlock(t);
      builder->problem()->AddResidualBlock(cost, nullptr, blocks);
      ++*num_blocks;
    }
  }
  return Status::OK();
}

Status AddRigidity(double weight, const ProblemOptions&,
                   ProblemBuilder* builder, int* num_blocks) {
  const Model& model = *builder->model();
  // The terms' cost functions hold no per-block data: one serves every
  // block of the term (problems/problem_builder.h owns it).
  ceres::CostFunction* cost = builder->Own(std::unique_ptr<ceres::CostFunction>(
      RigidityError::Create(std::sqrt(weight))));
  for (int t = 0; t < model.num_frames; ++t) {
    for (int c = 1; c < model.num_cameras; ++c) {
      builder->problem()->AddResidualBlock(
          cost, nullptr,
          {builder->RotationBlock(t, c), builder->RotationBlock(t, 0),
           builder->RigRotationBlock(c), builder->ScaleBlock(t, c),
           builder->RigScaleBlock(c)});
      ++*num_blocks;
    }
  }
  for (int c = 1; c < model.num_cameras; ++c) {
    builder->SetRotationManifold(builder->RigRotationBlock(c));
  }
  return Status::OK();
}

Status AddTemporalWeights(double weight, const ProblemOptions&,
                          ProblemBuilder* builder, int* num_blocks) {
  const Model& model = *builder->model();
  ceres::CostFunction* cost = builder->Own(std::unique_ptr<ceres::CostFunction>(
      WeightsTemporalError::Create(model.num_bases, std::sqrt(weight))));
  for (int t = 1; t < model.num_frames; ++t) {
    builder->problem()->AddResidualBlock(
        cost, nullptr, builder->WeightsBlock(t), builder->WeightsBlock(t - 1));
    ++*num_blocks;
  }
  return Status::OK();
}

Status AddTemporalRotations(double weight, const ProblemOptions&,
                            ProblemBuilder* builder, int* num_blocks) {
  const Model& model = *builder->model();
  ceres::CostFunction* cost = builder->Own(std::unique_ptr<ceres::CostFunction>(
      RotationTemporalError::Create(std::sqrt(weight))));
  for (int t = 1; t < model.num_frames; ++t) {
    for (int c = 0; c < model.num_cameras; ++c) {
      builder->problem()->AddResidualBlock(cost, nullptr,
                                           builder->RotationBlock(t, c),
                                           builder->RotationBlock(t - 1, c));
      ++*num_blocks;
    }
  }
  return Status::OK();
}

Status AddTemporalShape(double weight, const ProblemOptions&,
                        ProblemBuilder* builder, int* num_blocks) {
  const Model& model = *builder->model();
  ceres::CostFunction* cost = builder->Own(
      std::make_unique<ShapeTemporalError>(model.num_bases, std::sqrt(weight)));
  for (int t = 1; t < model.num_frames; ++t) {
    for (int p = 0; p < model.num_points; ++p) {
      builder->problem()->AddResidualBlock(
          cost, nullptr,
          {builder->WeightsBlock(t), builder->WeightsBlock(t - 1),
           builder->BasisBlock(p)});
      ++*num_blocks;
    }
  }
  return Status::OK();
}

Status AddDeformation(double weight, const ProblemOptions&,
                      ProblemBuilder* builder, int* num_blocks) {
  Model& model = *builder->model();
  // The residual leaves basis shape 1 free; starting with basis shape 1 the
  // mean shape puts the start's rigid part there (the shapes are unchanged).
  model.MakeFirstBasisTheMean();
  ceres::CostFunction* cost = builder->Own(
      std::make_unique<DeformationError>(model.num_bases, std::sqrt(weight)));
  for (int t = 0; t < model.num_frames; ++t) {
    if (!builder->problem()->HasParameterBlock(builder->WeightsBlock(t)))
      continue;
    for (int p = 0; p < model.num_points; ++p) {
      if (!builder->problem()->HasParameterBlock(builder->BasisBlock(p)))
        continue;
      builder->problem()->AddResidualBlock(
          cost, nullptr, builder->WeightsBlock(t), builder->BasisBlock(p));
      ++*num_blocks;
    }
  }
  return Status::OK();
}

Status AddRotationAcceleration(double weight, const ProblemOptions&,
                               ProblemBuilder* builder, int* num_blocks) {
  const Model& model = *builder->model();
  const double scale =
      std::sqrt(weight) * builder->measurements().ImageSpreadRms();
  ceres::CostFunction* cost = builder->Own(std::unique_ptr<ceres::CostFunction>(
      RotationAccelerationError::Create(scale)));
  for (int t = 1; t + 1 < model.num_frames; ++t) {
    for (int c = 0; c < model.num_cameras; ++c) {
      builder->problem()->AddResidualBlock(
          cost, nullptr,
          {builder->RotationBlock(t + 1, c), builder->RotationBlock(t, c),
           builder->RotationBlock(t - 1, c)});
      ++*num_blocks;
    }
  }
  return Status::OK();
}

}  // namespace

const std::vector<ExtraTerm>& ExtraTerms() {
  // name, units of λ, λ in (input units)², meaning, min_cameras, add.
  static const std::vector<ExtraTerm> terms = {
      {kSmoothnessTerm, "dimensionless", false,
       "Delaunay-neighbour smoothness of every frame's shape, "
       "S_t[:,i] - sum_j w_ij S_t[:,j] per frame and point (w_ij: the "
       "neighbours' affine combination that gives point i's image "
       "position), averaged over the frames: bends the surface, not its "
       "size or slant; points seen in few frames "
       "(problems/smoothness_error.h)",
       1, AddSmoothness},
      {kRigidityTerm, "(input units / rad)^2", true,
       "multi-camera rigidity, log(R_tc R_t0^T R_rig,c^T) and s_tc - s_rig,c: "
       "synchronised cameras on a rigid rig (problems/rigidity_error.h)",
       2, AddRigidity},
      {kTemporalTerm, "(input units)^2", true,
       "temporal smoothness of the weights, l_t - l_(t-1): video-like input "
       "(problems/temporal_error.h)",
       1, AddTemporalWeights},
      {kTemporalRotationsTerm, "(input units / rad)^2", true,
       "temporal smoothness of the rotations, log(R_t R_(t-1)^T); keep it far "
       "below --temporal, it trades real rotation for deformation "
       "(problems/temporal_error.h)",
       1, AddTemporalRotations},
      {kTemporalShapeTerm, "dimensionless", false,
       "temporal smoothness of the 3D shape in the object frame, S_t - S_(t-1) "
       "per point: video / motion capture with K near P/3 "
       "(problems/temporal_error.h)",
       1, AddTemporalShape},
      {kRotationAccelerationTerm, "dimensionless", false,
       "constant angular velocity, log(R_(t+1) R_t^T) - log(R_t R_(t-1)^T), "
       "scaled by the data's spread (problems/temporal_error.h)",
       1, AddRotationAcceleration},
      {kDeformationTerm, "dimensionless", false,
       "deformation, sum_(k>=2) l_tk S_k per point: the shape away from "
       "basis shape 1 up to the frame's scale, object frame: any input "
       "(problems/deformation_error.h)",
       1, AddDeformation},
  };
  return terms;
}

Status ExtraTerm::CheckCameras(int num_cameras) const {
  if (num_cameras >= min_cameras) return Status::OK();
  return Status::Error(
      "needs data from M >= " + std::to_string(min_cameras) +
      " synchronised cameras, got M = " + std::to_string(num_cameras));
}

const ExtraTerm* FindExtraTerm(const std::string& name) {
  for (const ExtraTerm& term : ExtraTerms()) {
    if (name == term.name) return &term;
  }
  return nullptr;
}

Status AddExtraTerms(const ProblemOptions& options, ProblemBuilder* builder,
                     std::vector<int>* num_blocks) {
  CHECK(builder != nullptr);
  NRSFM_RETURN_IF_ERROR(options.Check().WithContext("problem options"));
  const std::vector<ExtraTerm>& terms = ExtraTerms();
  std::vector<int> counts(terms.size(), 0);
  const int num_cameras = builder->model()->num_cameras;
  for (const ExtraTerm& term : terms) {
    if (!(options.TermWeight(term.name) > 0.0)) continue;
    NRSFM_RETURN_IF_ERROR(term.CheckCameras(num_cameras)
                              .WithContext(std::string(term.name) + " term"));
  }
  for (std::size_t i = 0; i < terms.size(); ++i) {
    const double weight = options.TermWeight(terms[i].name);
    if (weight == 0.0) continue;
    NRSFM_RETURN_IF_ERROR(
        terms[i]
            .add(weight, options, builder, &counts[i])
            .WithContext(std::string(terms[i].name) + " term"));
  }
  builder->SetConstantBlocks(options);
  if (num_blocks != nullptr) *num_blocks = std::move(counts);
  return Status::OK();
}

}  // namespace nrsfm
