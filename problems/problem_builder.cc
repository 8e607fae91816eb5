#include "problems/problem_builder.h"

#include <glog/logging.h>

#include <cmath>
#include <sstream>
#include <unordered_set>

#include "problems/perspective_error.h"
#include "problems/reprojection_cost_function.h"

namespace nrsfm {
namespace {

template <int K>
std::unique_ptr<ceres::CostFunction> CreateFixedK(
    bool with_scale, const Eigen::Vector2d& observation, double sqrt_weight) {
  return std::make_unique<ReprojectionCostFunction<K>>(
      K, with_scale, observation, sqrt_weight);
}

ceres::Problem::Options MakeProblemOptions() {
  ceres::Problem::Options options;
  options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  // The blocks are the model's storage; the caller owns them. The builder
  // owns the cost functions and losses.
  return options;
}

}  // namespace

std::unique_ptr<ceres::CostFunction> CreateReprojectionCostFunction(
    int num_bases, bool with_scale, const Eigen::Vector2d& observation,
    double sqrt_weight) {
  CHECK_GE(num_bases, 1);
  const Eigen::Vector2d& o = observation;
  const double w = sqrt_weight;
  static_assert(kMaxStaticBases == 16, "update the switch below");
  switch (num_bases) {
    case 1:
      return CreateFixedK<1>(with_scale, o, w);
    case 2:
      return CreateFixedK<2>(with_scale, o, w);
    case 3:
      return CreateFixedK<3>(with_scale, o, w);
    case 4:
      return CreateFixedK<4>(with_scale, o, w);
    case 5:
      return CreateFixedK<5>(with_scale, o, w);
    case 6:
      return CreateFixedK<6>(with_scale, o, w);
    case 7:
      return CreateFixedK<7>(with_scale, o, w);
    case 8:
      return CreateFixedK<8>(with_scale, o, w);
    case 9:
      return CreateFixedK<9>(with_scale, o, w);
    case 10:
      return CreateFixedK<10>(with_scale, o, w);
    case 11:
      return CreateFixedK<11>(with_scale, o, w);
    case 12:
      return CreateFixedK<12>(with_scale, o, w);
    case 13:
      return CreateFixedK<13>(with_scale, o, w);
    case 14:
      return CreateFixedK<14>(with_scale, o, w);
    case 15:
      return CreateFixedK<15>(with_scale, o, w);
    case 16:
      return CreateFixedK<16>(with_scale, o, w);
    default:
      return std::make_unique<ReprojectionCostFunction<Eigen::Dynamic>>(
          num_bases, with_scale, o, w);
  }
}

ProblemBuilder::ProblemBuilder(const Measurements* measurements, Model* model)
    : measurements_(measurements),
      model_(model),
      problem_(MakeProblemOptions()) {
  CHECK(measurements != nullptr);
  CHECK(model != nullptr);
}

double* ProblemBuilder::RotationBlock(int frame, int camera) {
  return model_->rotations.col(model_->View(frame, camera)).data();
}

double* ProblemBuilder::TranslationBlock(int frame, int camera) {
  return model_->translations.col(model_->View(frame, camera)).data();
}

double* ProblemBuilder::WeightsBlock(int frame) {
  return model_->weights.col(frame).data();
}

double* ProblemBuilder::BasisBlock(int point) {
  return model_->basis.col(point).data();
}

double* ProblemBuilder::DepthBlock(int frame, int camera) {
  return model_->depths.data() + model_->View(frame, camera);
}

double* ProblemBuilder::ScaleBlock(int frame, int camera) {
  CHECK_GE(camera, 1) << "camera 0 has no scale block (s = 1)";
  return model_->scales.data() + model_->View(frame, camera);
}

double* ProblemBuilder::RigRotationBlock(int camera) {
  CHECK(camera >= 1 && camera < model_->num_cameras) << "camera " << camera;
  return model_->rig_rotations.col(camera - 1).data();
}

double* ProblemBuilder::RigScaleBlock(int camera) {
  CHECK(camera >= 1 && camera < model_->num_cameras) << "camera " << camera;
  return model_->rig_scales.data() + camera - 1;
}

ceres::LossFunction* ProblemBuilder::LossForWeight(
    const ProblemOptions& options, double weight) {
  if (options.robust_loss == RobustLoss::kNone) return nullptr;
  std::unique_ptr<ceres::LossFunction>& loss = losses_[weight];
  if (loss == nullptr) {
    // The residual is sqrt(w)·e; a loss of scale a·sqrt(w) on it equals
    // w · ρ_a(||e||²) for both losses, so `a` stays in input units.
    const double scale = options.robust_scale * std::sqrt(weight);
    if (options.robust_loss == RobustLoss::kHuber) {
      loss = std::make_unique<ceres::HuberLoss>(scale);
    } else {
      loss = std::make_unique<ceres::CauchyLoss>(scale);
    }
  }
  return loss.get();
}

Status ProblemBuilder::CheckInputs(const ProblemOptions& options,
                                   const Measurements& m, const Model& model) {
  NRSFM_RETURN_IF_ERROR(options.Check().WithContext("problem options"));
  NRSFM_RETURN_IF_ERROR(m.Validate());
  NRSFM_RETURN_IF_ERROR(model.Validate());
  if (m.num_frames != model.num_frames || m.num_cameras != model.num_cameras ||
      m.num_points != model.num_points) {
    std::ostringstream msg;
    msg << "model (F = " << model.num_frames << ", M = " << model.num_cameras
        << ", P = " << model.num_points
        << ") does not match the measurements (F = " << m.num_frames
        << ", M = " << m.num_cameras << ", P = " << m.num_points << ")";
    return Status::Error(msg.str());
  }
  const bool weighted = options.observation_weights.size() > 0;
  if (weighted && (options.observation_weights.rows() != m.NumViews() ||
                   options.observation_weights.cols() != m.num_points)) {
    std::ostringstream msg;
    msg << "observation_weights is " << options.observation_weights.rows()
        << " x " << options.observation_weights.cols() << ", expected "
        << m.NumViews() << " x " << m.num_points << " (views x points)";
    return Status::Error(msg.str());
  }
  if (m.num_cameras > 1) {
    for (int t = 0; t < m.num_frames; ++t) {
      if (model.scales(model.View(t, 0)) != 1.0) {
        std::ostringstream msg;
        msg << "model: the scale of camera 0 must be 1, frame " << t << " has "
            << model.scales(model.View(t, 0));
        return Status::Error(msg.str());
      }
    }
  }
  return Status::OK();
}

ceres::CostFunction* ProblemBuilder::Own(
    std::unique_ptr<ceres::CostFunction> cost) {
  cost_functions_.push_back(std::move(cost));
  return cost_functions_.back().get();
}

ceres::ResidualBlockId ProblemBuilder::AddResidualBlock(
    std::unique_ptr<ceres::CostFunction> cost, ceres::LossFunction* loss,
    const std::vector<double*>& blocks) {
  return problem_.AddResidualBlock(Own(std::move(cost)), loss, blocks);
}

Status ProblemBuilder::AddReprojectionTerms(const ProblemOptions& options) {
  CHECK_EQ(num_reprojection_terms_, 0) << "AddReprojectionTerms called twice";
  NRSFM_RETURN_IF_ERROR(CheckInputs(options, *measurements_, *model_));
  const Measurements& m = *measurements_;
  Model& model = *model_;
  const bool weighted = options.observation_weights.size() > 0;

  const int num_bases = model.num_bases;
  const bool perspective = model.camera == CameraModel::kPerspective;
  for (int t = 0; t < m.num_frames; ++t) {
    for (int c = 0; c < m.num_cameras; ++c) {
      const int view = m.View(t, c);
      const bool with_scale = c > 0 && !perspective;
      for (int p = 0; p < m.num_points; ++p) {
        if (!m.visible(view, p)) continue;
        const double weight =
            weighted ? options.observation_weights(view, p) : 1.0;
        if (weight == 0.0) continue;
        std::unique_ptr<ceres::CostFunction> cost(
            perspective ? PerspectiveReprojectionError::Create(
                              num_bases, model.intrinsics.col(c),
                              m.Observation(t, c, p), std::sqrt(weight))
                        : CreateReprojectionCostFunction(num_bases, with_scale,
                                                         m.Observation(t, c, p),
                                                         std::sqrt(weight))
                              .release());
        std::vector<double*> blocks = {RotationBlock(t, c),
                                       TranslationBlock(t, c), WeightsBlock(t),
                                       BasisBlock(p)};
        if (with_scale) blocks.push_back(ScaleBlock(t, c));
        if (perspective) blocks.push_back(DepthBlock(t, c));
        AddResidualBlock(std::move(cost), LossForWeight(options, weight),
                         blocks);
        ++num_reprojection_terms_;
      }
    }
  }

  for (int t = 0; t < m.num_frames; ++t) {
    for (int c = 0; c < m.num_cameras; ++c) {
      if (problem_.HasParameterBlock(RotationBlock(t, c))) {
        SetRotationManifold(RotationBlock(t, c));
      }
    }
  }
  SetConstantBlocks(options);
  if (perspective) {
    // The gauges of pinhole views (docs/camera.md): per frame, the shape and
    // the translation scale together (X_t → α_t X_t leaves its image), and
    // the basis shifts with the translations (S_k → S_k + d_k). Every depth
    // t_z and the basis of the most observed point are held where the start
    // put them: any answer has an equal one with these values.
    for (int view = 0; view < m.NumViews(); ++view) {
      double* depth = DepthBlock(view / m.num_cameras, view % m.num_cameras);
      if (problem_.HasParameterBlock(depth)) {
        problem_.SetParameterBlockConstant(depth);
      }
    }
    int anchor = 0;
    const Eigen::VectorXi seen = m.VisiblePerPoint();
    seen.maxCoeff(&anchor);
    if (problem_.HasParameterBlock(BasisBlock(anchor))) {
      problem_.SetParameterBlockConstant(BasisBlock(anchor));
    }
  }
  return Status::OK();
}

void ProblemBuilder::SetRotationManifold(double* block) {
  CHECK(problem_.HasParameterBlock(block));
  problem_.SetManifold(block, &rotation_manifold_);
}

void ProblemBuilder::SetConstantBlocks(const ProblemOptions& options) {
  auto set_constant = [this](double* block) {
    if (problem_.HasParameterBlock(block))
      problem_.SetParameterBlockConstant(block);
  };
  const Model& model = *model_;
  for (int t = 0; t < model.num_frames; ++t) {
    for (int c = 0; c < model.num_cameras; ++c) {
      if (options.constant_rotations) set_constant(RotationBlock(t, c));
      if (options.constant_translations) set_constant(TranslationBlock(t, c));
      // A perspective view has no scale (a rigidity term may still hold one).
      if ((options.constant_scales ||
           model.camera == CameraModel::kPerspective) &&
          c > 0) {
        set_constant(ScaleBlock(t, c));
      }
      if (options.constant_translations) set_constant(DepthBlock(t, c));
    }
    if (options.constant_weights) set_constant(WeightsBlock(t));
  }
  if (options.constant_basis) {
    for (int p = 0; p < model.num_points; ++p) set_constant(BasisBlock(p));
  }
  if (options.constant_rig) {
    for (int c = 1; c < model.num_cameras; ++c) {
      set_constant(RigRotationBlock(c));
      set_constant(RigScaleBlock(c));
    }
  }
}

std::vector<double*> ProblemBuilder::PointBlocks() {
  std::vector<double*> blocks;
  for (int p = 0; p < model_->num_points; ++p) {
    if (problem_.HasParameterBlock(BasisBlock(p)))
      blocks.push_back(BasisBlock(p));
  }
  return blocks;
}

std::vector<double*> ProblemBuilder::NonPointBlocks() {
  const std::vector<double*> points = PointBlocks();
  const std::unordered_set<double*> point_set(points.begin(), points.end());
  std::vector<double*> all;
  problem_.GetParameterBlocks(&all);
  std::vector<double*> blocks;
  for (double* block : all) {
    if (point_set.count(block) == 0) blocks.push_back(block);
  }
  return blocks;
}

std::vector<std::vector<double*>> ProblemBuilder::NonPointBlockGroups() {
  auto in = [](const double* block, const auto& matrix) {
    return block >= matrix.data() && block < matrix.data() + matrix.size();
  };
  std::vector<std::vector<double*>> kinds(5);
  std::vector<std::vector<double*>> others;
  for (double* block : NonPointBlocks()) {
    if (in(block, model_->rotations)) {
      kinds[0].push_back(block);
    } else if (in(block, model_->translations)) {
      kinds[1].push_back(block);
    } else if (in(block, model_->weights)) {
      kinds[2].push_back(block);
    } else if (in(block, model_->scales)) {
      kinds[3].push_back(block);
    } else if (in(block, model_->depths)) {
      kinds[4].push_back(block);
    } else {
      others.push_back({block});
    }
  }
  std::vector<std::vector<double*>> groups;
  for (std::vector<double*>& kind : kinds) {
    if (!kind.empty()) groups.push_back(std::move(kind));
  }
  groups.insert(groups.end(), others.begin(), others.end());
  return groups;
}

bool ProblemBuilder::PointBlocksAreIndependent() const {
  const double* begin = model_->basis.data();
  const double* end = begin + model_->basis.size();
  std::vector<ceres::ResidualBlockId> residual_blocks;
  problem_.GetResidualBlocks(&residual_blocks);
  std::vector<double*> blocks;
  for (ceres::ResidualBlockId id : residual_blocks) {
    problem_.GetParameterBlocksForResidualBlock(id, &blocks);
    int num_point_blocks = 0;
    for (const double* block : blocks) {
      if (block >= begin && block < end) ++num_point_blocks;
    }
    if (num_point_blocks > 1) return false;
  }
  return true;
}

}  // namespace nrsfm
