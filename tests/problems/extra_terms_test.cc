// The table of extra terms (problems/extra_terms.h): what it promises every
// reader (unique names and flags), the residual blocks each term adds, that
// λ multiplies the term's cost, and the errors.
#include "problems/extra_terms.h"

#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/synthetic.h"
#include "problems/delaunay_edges.h"

namespace nrsfm {
namespace {

constexpr int kFrames = 6;
constexpr int kPoints = 12;
constexpr int kCameras = 2;

SyntheticSequence Shoe(int cameras) {
  ShoeOptions options;
  options.num_frames = kFrames;
  options.num_points = kPoints;
  options.num_cameras = cameras;
  options.self_occlusion = false;
  options.noise_stddev = 0.01;
  SyntheticSequence sequence;
  EXPECT_TRUE(GenerateShoe(options, &sequence).ok());
  return sequence;
}

// Ceres cost of the problem at the model's current values.
double Cost(ProblemBuilder* builder) {
  double cost = 0.0;
  EXPECT_TRUE(builder->problem()->Evaluate(ceres::Problem::EvaluateOptions(),
                                           &cost, nullptr, nullptr, nullptr));
  return cost;
}

TEST(ExtraTerms, TableNamesAreUniqueAndDescribed) {
  std::set<std::string> names;
  for (const ExtraTerm& term : ExtraTerms()) {
    EXPECT_TRUE(names.insert(term.name).second) << term.name;
    EXPECT_GT(std::string(term.units).size(), 0u) << term.name;
    EXPECT_GT(std::string(term.meaning).size(), 0u) << term.name;
    EXPECT_GE(term.min_cameras, 1) << term.name;
    EXPECT_NE(term.add, nullptr) << term.name;
    EXPECT_EQ(FindExtraTerm(term.name), &term);
  }
  EXPECT_EQ(names.size(), 7u);
  EXPECT_EQ(FindExtraTerm(kTemporalTerm)->name, std::string("temporal"));
  EXPECT_EQ(FindExtraTerm("--temporal"), nullptr);
}

// Residual blocks per term on F = 6 frames, P = 12 points, M = 2 cameras.
TEST(ExtraTerms, EachTermAddsItsCountOfResidualBlocks) {
  SyntheticSequence s = Shoe(kCameras);
  std::vector<NeighbourEdge> edges;
  ASSERT_TRUE(ComputeDelaunayEdges(s.measurements, DelaunayEdgesOptions(), &edges).ok());
  const int expected[] = {
      static_cast<int>(edges.size()),  // smoothness: one per neighbour edge
      kFrames * (kCameras - 1),        // rigidity: (t, c ≥ 1)
      kFrames - 1,                     // temporal: t ≥ 1
      (kFrames - 1) * kCameras,        // temporal_rotations: (t ≥ 1, c)
      (kFrames - 1) * kPoints,         // temporal_shape: (t ≥ 1, p)
      (kFrames - 2) * kCameras,        // rotation_acceleration: (1 ≤ t ≤ F − 2, c)
      kFrames * kPoints,               // deformation: (t, p)
  };
  ASSERT_EQ(ExtraTerms().size(), std::size(expected));
  ProblemOptions options;
  for (const ExtraTerm& term : ExtraTerms()) options.term_weights[term.name] = 2.0;
  Model model = s.truth;
  ProblemBuilder builder(&s.measurements, &model);
  ASSERT_TRUE(builder.AddReprojectionTerms(options).ok());
  const int reprojection = builder.problem()->NumResidualBlocks();
  EXPECT_EQ(reprojection, kFrames * kCameras * kPoints);
  std::vector<int> counts;
  ASSERT_TRUE(AddExtraTerms(options, &builder, &counts).ok());
  ASSERT_EQ(counts.size(), std::size(expected));
  int total = reprojection;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    EXPECT_EQ(counts[i], expected[i]) << ExtraTerms()[i].name;
    total += counts[i];
  }
  EXPECT_GT(counts[0], kPoints);  // a triangulation of 12 points
  EXPECT_EQ(builder.problem()->NumResidualBlocks(), total);
  // The rigidity term brings the rig blocks of camera 1.
  EXPECT_TRUE(builder.problem()->HasParameterBlock(builder.RigRotationBlock(1)));
  EXPECT_TRUE(builder.problem()->HasParameterBlock(builder.RigScaleBlock(1)));
  EXPECT_FALSE(builder.problem()->IsParameterBlockConstant(builder.RigScaleBlock(1)));
}

// Weights are explicit: λ multiplies the term's cost. Away from the truth
// (perturbed rig and weights) every term has a non-zero cost.
TEST(ExtraTerms, WeightMultipliesTheTermsCost) {
  SyntheticSequence s = Shoe(kCameras);
  Model model = s.truth;
  model.rig_rotations.col(0) += Eigen::Vector3d(0.05, -0.02, 0.03);
  model.rig_scales(0) += 0.1;
  for (int t = 0; t < kFrames; ++t) model.weights(1, t) += 0.01 * t * t;
  ProblemOptions none;
  ProblemBuilder data_only(&s.measurements, &model);
  ASSERT_TRUE(data_only.AddReprojectionTerms(none).ok());
  const double data_cost = Cost(&data_only);
  for (const ExtraTerm& term : ExtraTerms()) {
    SCOPED_TRACE(term.name);
    double term_cost[2];
    for (int i = 0; i < 2; ++i) {
      ProblemOptions options;
      options.term_weights[term.name] = i == 0 ? 1.0 : 4.0;
      ProblemBuilder builder(&s.measurements, &model);
      ASSERT_TRUE(builder.AddReprojectionTerms(options).ok());
      ASSERT_TRUE(AddExtraTerms(options, &builder).ok());
      term_cost[i] = Cost(&builder) - data_cost;
    }
    EXPECT_GT(term_cost[0], 1e-8);
    EXPECT_NEAR(term_cost[1], 4.0 * term_cost[0], 1e-9 * term_cost[1]);
  }
}

TEST(ExtraTerms, ZeroWeightAddsNothingAndConstantRigHoldsTheRig) {
  SyntheticSequence s = Shoe(kCameras);
  ProblemOptions options;
  options.term_weights["temporal_shape"] = 0.0;
  options.term_weights["rigidity"] = 1.0;
  options.constant_rig = true;
  Model model = s.truth;
  ProblemBuilder builder(&s.measurements, &model);
  ASSERT_TRUE(builder.AddReprojectionTerms(options).ok());
  std::vector<int> counts;
  ASSERT_TRUE(AddExtraTerms(options, &builder, &counts).ok());
  EXPECT_EQ(counts, (std::vector<int>{0, kFrames, 0, 0, 0, 0, 0}));
  EXPECT_TRUE(builder.problem()->IsParameterBlockConstant(builder.RigRotationBlock(1)));
  EXPECT_TRUE(builder.problem()->IsParameterBlockConstant(builder.RigScaleBlock(1)));
}

TEST(ExtraTerms, ErrorsNameTheTerm) {
  SyntheticSequence mono = Shoe(1);
  ProblemOptions options;
  options.term_weights["rigidity"] = 1.0;
  Model model = mono.truth;
  ProblemBuilder builder(&mono.measurements, &model);
  ASSERT_TRUE(builder.AddReprojectionTerms(options).ok());
  Status status = AddExtraTerms(options, &builder);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("rigidity term: needs data from M >= 2"),
            std::string::npos)
      << status.message();

  ProblemOptions unknown;
  unknown.term_weights["temporal_weights"] = 1.0;
  status = unknown.Check();
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("no term \"temporal_weights\""), std::string::npos)
      << status.message();
  EXPECT_NE(status.message().find("rigidity, temporal, temporal_rotations"), std::string::npos)
      << status.message();
}

}  // namespace
}  // namespace nrsfm
