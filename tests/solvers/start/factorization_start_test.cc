#include "solvers/start/factorization_start.h"

#include <gtest/gtest.h>

#include "core/eval/metrics.h"
#include "core/synthetic/synthetic.h"

namespace nrsfm {
namespace {

Measurements Centered(const Measurements& m) {
  Measurements centered = m;
  centered.W = m.W.colwise() - m.W.rowwise().mean();
  return centered;
}

TEST(FactorizationStart, RigidDataIsTomasiKanadeExactly) {
  RandomBasisOptions options;
  options.num_frames = 60;
  options.num_points = 25;
  options.num_bases = 1;
  SyntheticSequence sequence;
  ASSERT_TRUE(GenerateRandomBasis(options, &sequence).ok());
  Model model;
  FactorizationStartSummary summary;
  ASSERT_TRUE(
      FactorizationStart(Centered(sequence.measurements), 1, &model, &summary)
          .ok());
  // A 1 × 6 block is always rank 1.
  EXPECT_EQ(summary.mean_subblock_rank1_defect, 0.0);
  EXPECT_LT(
      ComputeE3D(CameraFrameShapes(sequence.truth), CameraFrameShapes(model)),
      1e-10);
}

// Torresani et al. 2001: the SVD's Q̂ is Q A for an arbitrary 3K × 3K A, so the
// reordered blocks are far from rank 1 for K > 1, even without noise.
TEST(FactorizationStart, SubBlocksAreNotRankOneForSeveralBases) {
  RandomBasisOptions options;
  options.num_frames = 100;
  options.num_points = 30;
  options.num_bases = 3;
  SyntheticSequence sequence;
  ASSERT_TRUE(GenerateRandomBasis(options, &sequence).ok());
  Model model;
  FactorizationStartSummary summary;
  ASSERT_TRUE(
      FactorizationStart(Centered(sequence.measurements), 3, &model, &summary)
          .ok());
  ASSERT_TRUE(model.Validate().ok());
  // Measured 0.48 (seed 1): σ₂ of a reordered block is half its σ₁.
  EXPECT_GT(summary.mean_subblock_rank1_defect, 0.1);
}

TEST(FactorizationStart, TooManyBasesIsAnError) {
  RandomBasisOptions options;
  options.num_frames = 4;
  options.num_points = 30;
  options.num_bases = 1;
  SyntheticSequence sequence;
  ASSERT_TRUE(GenerateRandomBasis(options, &sequence).ok());
  Model model;
  FactorizationStartSummary summary;
  EXPECT_FALSE(
      FactorizationStart(Centered(sequence.measurements), 3, &model, &summary)
          .ok());
}

}  // namespace
}  // namespace nrsfm
