// The table of extra terms (problems/extra_terms.h): what it promises every
// reader (unique names and flags), that every row adds residual blocks and
// λ multiplies its cost, and the errors. Every expectation here derives from
// ExtraTerms(), so a new row needs no edit in this file: how many blocks each
// term adds is checked in the term's own test (TermBlockCount,
// tests/problems/term_test_util.h).
#include "problems/extra_terms.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/synthetic/synthetic.h"
#include "tests/problems/term_test_util.h"

namespace nrsfm {
namespace {

using testing_util::kTermFrames;
using testing_util::kTermPoints;
using testing_util::TermBlockCount;
using testing_util::TermBlockCounts;
using testing_util::TermTestShoe;

// Cameras of the test sequence: enough for every row of the table, and at
// least two (a rig to perturb).
int TestCameras() {
  int cameras = 2;
  for (const ExtraTerm& term : ExtraTerms())
    cameras = std::max(cameras, term.min_cameras);
  return cameras;
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
  EXPECT_EQ(names.size(), ExtraTerms().size());
  ASSERT_FALSE(ExtraTerms().empty());
  const std::string first = ExtraTerms()[0].name;
  EXPECT_EQ(FindExtraTerm(first)->name, first);
  EXPECT_EQ(FindExtraTerm("--" + first), nullptr);
  EXPECT_EQ(FindExtraTerm(""), nullptr);
}

// Every row adds residual blocks, and adding all rows at once adds each
// row's own count (the counts themselves: each term's own test).
TEST(ExtraTerms, EachTermAddsBlocksAndAllTogetherAddTheirOwnCounts) {
  const SyntheticSequence s = TermTestShoe(TestCameras());
  std::map<std::string, double> all;
  for (const ExtraTerm& term : ExtraTerms()) all[term.name] = 2.0;
  const std::vector<int> together = TermBlockCounts(all, s);
  ASSERT_EQ(together.size(), ExtraTerms().size());
  for (std::size_t i = 0; i < ExtraTerms().size(); ++i) {
    const std::string name = ExtraTerms()[i].name;
    const int alone = TermBlockCount(name, s);
    EXPECT_GT(alone, 0) << name;
    EXPECT_EQ(together[i], alone) << name;
    // Alone, no other row adds anything.
    const std::vector<int> counts = TermBlockCounts({{name, 2.0}}, s);
    for (std::size_t j = 0; j < counts.size(); ++j) {
      if (j != i) {
        EXPECT_EQ(counts[j], 0) << name << " then " << ExtraTerms()[j].name;
      }
    }
  }
  ProblemOptions options;
  options.term_weights = all;
  Measurements measurements = s.measurements;
  Model model = s.truth;
  ProblemBuilder builder(&measurements, &model);
  ASSERT_TRUE(builder.AddReprojectionTerms(options).ok());
  const int reprojection = builder.problem()->NumResidualBlocks();
  EXPECT_EQ(reprojection, kTermFrames * TestCameras() * kTermPoints);
  std::vector<int> counts;
  ASSERT_TRUE(AddExtraTerms(options, &builder, &counts).ok());
  int total = reprojection;
  for (int count : counts) total += count;
  EXPECT_EQ(builder.problem()->NumResidualBlocks(), total);
}

// A row whose min_cameras exceeds M is refused with the term's name.
TEST(ExtraTerms, TooFewCamerasNameTheTerm) {
  for (const ExtraTerm& term : ExtraTerms()) {
    if (term.min_cameras <= 1) continue;
    SCOPED_TRACE(term.name);
    SyntheticSequence s = TermTestShoe(term.min_cameras - 1);
    ProblemOptions options;
    options.term_weights[term.name] = 1.0;
    Model model = s.truth;
    ProblemBuilder builder(&s.measurements, &model);
    ASSERT_TRUE(builder.AddReprojectionTerms(options).ok());
    const Status status = AddExtraTerms(options, &builder);
    ASSERT_FALSE(status.ok());
    EXPECT_NE(status.message().find(std::string(term.name) +
                                    " term: needs data from M >= " +
                                    std::to_string(term.min_cameras)),
              std::string::npos)
        << status.message();
  }
}

// Weights are explicit: λ multiplies the term's cost. Away from the truth
// (perturbed rig and weights) every term has a non-zero cost.
TEST(ExtraTerms, WeightMultipliesTheTermsCost) {
  SyntheticSequence s = TermTestShoe(TestCameras());
  Model model = s.truth;
  model.rig_rotations.col(0) += Eigen::Vector3d(0.05, -0.02, 0.03);
  model.rig_scales(0) += 0.1;
  for (int t = 0; t < kTermFrames; ++t) model.weights(1, t) += 0.01 * t * t;
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

// The rigidity term's rig blocks follow ProblemOptions::constant_rig; a
// zero weight leaves a term out.
TEST(ExtraTerms, ZeroWeightAddsNothingAndConstantRigHoldsTheRig) {
  SyntheticSequence s = TermTestShoe(2);
  ProblemOptions options;
  for (const ExtraTerm& term : ExtraTerms())
    options.term_weights[term.name] = 0.0;
  options.term_weights[kRigidityTerm] = 1.0;
  options.constant_rig = true;
  Model model = s.truth;
  ProblemBuilder builder(&s.measurements, &model);
  ASSERT_TRUE(builder.AddReprojectionTerms(options).ok());
  std::vector<int> counts;
  ASSERT_TRUE(AddExtraTerms(options, &builder, &counts).ok());
  ASSERT_EQ(counts.size(), ExtraTerms().size());
  for (std::size_t i = 0; i < counts.size(); ++i) {
    const bool rigidity = ExtraTerms()[i].name == std::string(kRigidityTerm);
    EXPECT_EQ(counts[i] > 0, rigidity) << ExtraTerms()[i].name;
  }
  EXPECT_TRUE(
      builder.problem()->IsParameterBlockConstant(builder.RigRotationBlock(1)));
  EXPECT_TRUE(
      builder.problem()->IsParameterBlockConstant(builder.RigScaleBlock(1)));
}

TEST(ExtraTerms, UnknownNameListsTheTable) {
  ProblemOptions unknown;
  unknown.term_weights["temporal_weights"] = 1.0;
  const Status status = unknown.Check();
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("no term \"temporal_weights\""),
            std::string::npos)
      << status.message();
  std::string known;
  for (const ExtraTerm& term : ExtraTerms()) {
    known += (known.empty() ? "" : ", ") + std::string(term.name);
  }
  EXPECT_NE(status.message().find("(the terms are " + known + ")"),
            std::string::npos)
      << status.message();
}

}  // namespace
}  // namespace nrsfm
