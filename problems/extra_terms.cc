#include "problems/extra_terms.h"

#include <cmath>
#include <vector>

#include <glog/logging.h>

#include "problems/delaunay_edges.h"
#include "problems/rigidity_error.h"
#include "problems/smoothness_error.h"
#include "problems/temporal_error.h"

namespace nrsfm {

Status AddExtraTerms(const ProblemOptions& options, ProblemBuilder* builder,
                     ExtraTermCounts* counts) {
  CHECK(builder != nullptr);
  CHECK(counts != nullptr);
  *counts = ExtraTermCounts();
  NRSFM_RETURN_IF_ERROR(options.Check().WithContext("problem options"));
  const Measurements& m = builder->measurements();
  Model& model = *builder->model();
  const int num_frames = model.num_frames;
  const int num_cameras = model.num_cameras;
  if (options.rigidity_weight > 0.0 && num_cameras < 2) {
    return Status::Error(
        "rigidity_weight > 0 needs multi-camera data (M >= 2), got M = " +
        std::to_string(num_cameras));
  }
  std::vector<NeighbourEdge> edges;
  if (options.smoothness_weight > 0.0) {
    NRSFM_RETURN_IF_ERROR(
        ComputeDelaunayEdges(m, options.smoothness_edges, &edges,
                             &counts->reference_frame)
            .WithContext("smoothness term"));
  }
  ceres::Problem& problem = *builder->problem();

  const double sqrt_smoothness = std::sqrt(options.smoothness_weight);
  for (const NeighbourEdge& edge : edges) {
    problem.AddResidualBlock(
        SmoothnessError::Create(model.num_bases, sqrt_smoothness, edge.alpha),
        nullptr, builder->BasisBlock(edge.i), builder->BasisBlock(edge.j));
    ++counts->smoothness;
  }
  if (options.rigidity_weight > 0.0) {
    const double sqrt_weight = std::sqrt(options.rigidity_weight);
    for (int t = 0; t < num_frames; ++t) {
      for (int c = 1; c < num_cameras; ++c) {
        problem.AddResidualBlock(
            RigidityError::Create(sqrt_weight), nullptr,
            {builder->RotationBlock(t, c), builder->RotationBlock(t, 0),
             builder->RigRotationBlock(c), builder->ScaleBlock(t, c),
             builder->RigScaleBlock(c)});
        ++counts->rigidity;
      }
    }
  }
  if (options.temporal_weights_weight > 0.0) {
    const double sqrt_weight = std::sqrt(options.temporal_weights_weight);
    for (int t = 1; t < num_frames; ++t) {
      problem.AddResidualBlock(
          WeightsTemporalError::Create(model.num_bases, sqrt_weight), nullptr,
          builder->WeightsBlock(t), builder->WeightsBlock(t - 1));
      ++counts->temporal_weights;
    }
  }
  if (options.temporal_rotations_weight > 0.0) {
    const double sqrt_weight = std::sqrt(options.temporal_rotations_weight);
    for (int t = 1; t < num_frames; ++t) {
      for (int c = 0; c < num_cameras; ++c) {
        problem.AddResidualBlock(RotationTemporalError::Create(sqrt_weight),
                                 nullptr, builder->RotationBlock(t, c),
                                 builder->RotationBlock(t - 1, c));
        ++counts->temporal_rotations;
      }
    }
  }
  if (options.temporal_shape_weight > 0.0) {
    const double sqrt_weight = std::sqrt(options.temporal_shape_weight);
    for (int t = 1; t < num_frames; ++t) {
      for (int p = 0; p < model.num_points; ++p) {
        problem.AddResidualBlock(
            new ShapeTemporalError(model.num_bases, sqrt_weight), nullptr,
            {builder->WeightsBlock(t), builder->WeightsBlock(t - 1),
             builder->BasisBlock(p)});
        ++counts->temporal_shape;
      }
    }
  }
  if (options.rotation_acceleration_weight > 0.0) {
    const double scale =
        std::sqrt(options.rotation_acceleration_weight) * m.ImageSpreadRms();
    for (int t = 1; t + 1 < num_frames; ++t) {
      for (int c = 0; c < num_cameras; ++c) {
        problem.AddResidualBlock(RotationAccelerationError::Create(scale), nullptr,
                                 {builder->RotationBlock(t + 1, c),
                                  builder->RotationBlock(t, c),
                                  builder->RotationBlock(t - 1, c)});
        ++counts->rotation_acceleration;
      }
    }
  }

  // The constant flags, also on the blocks only these terms use.
  auto set_constant = [&problem](double* block) {
    if (problem.HasParameterBlock(block)) problem.SetParameterBlockConstant(block);
  };
  for (int t = 0; t < num_frames; ++t) {
    for (int c = 0; c < num_cameras; ++c) {
      if (options.constant_rotations) set_constant(builder->RotationBlock(t, c));
      if (options.constant_scales && c > 0) set_constant(builder->ScaleBlock(t, c));
    }
    if (options.constant_weights) set_constant(builder->WeightsBlock(t));
  }
  for (int p = 0; p < model.num_points; ++p) {
    if (options.constant_basis) set_constant(builder->BasisBlock(p));
  }
  for (int c = 1; c < num_cameras; ++c) {
    if (options.constant_rig) {
      set_constant(builder->RigRotationBlock(c));
      set_constant(builder->RigScaleBlock(c));
    }
  }
  return Status::OK();
}

}  // namespace nrsfm
