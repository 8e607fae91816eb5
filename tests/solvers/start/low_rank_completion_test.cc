#include "solvers/start/low_rank_completion.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/synthetic/synthetic.h"
#include "tests/synthetic_sequences.h"

namespace nrsfm {
namespace {

// Largest and RMS 2D error of the completed missing entries against the
// noise-free projections of the truth.
void MissingErrors(const SyntheticSequence& sequence,
                   const LowRankCompletion& completion, double* max_error,
                   double* rms_error) {
  const Measurements& m = sequence.measurements;
  double sum = 0.0;
  int count = 0;
  *max_error = 0.0;
  for (int t = 0; t < m.num_frames; ++t) {
    for (int c = 0; c < m.num_cameras; ++c) {
      const Eigen::Matrix2Xd truth = sequence.truth.Project(t, c);
      for (int p = 0; p < m.num_points; ++p) {
        if (m.visible(m.View(t, c), p)) continue;
        const double e =
            (completion.completed.block<2, 1>(m.Row(t, c), p) - truth.col(p))
                .norm();
        *max_error = std::max(*max_error, e);
        sum += e * e;
        ++count;
      }
    }
  }
  ASSERT_GT(count, 0);
  *rms_error = std::sqrt(sum / count);
}

SyntheticSequence RandomMissing(int num_bases, double noise, double missing) {
  return testing_util::RandomBasisSequence(120, 40, num_bases, noise, missing,
                                           5);
}

TEST(LowRankCompletion, RecoversMissingEntriesOfNoiseFreeData) {
  const SyntheticSequence sequence = RandomMissing(3, 0.0, 0.3);
  LowRankCompletionOptions options;
  int rank = 9;
  LowRankCompletion completion;
  ASSERT_TRUE(
      CompleteLowRankAffine(sequence.measurements, rank, options, &completion)
          .ok());
  double max_error = 0.0, rms_error = 0.0;
  MissingErrors(sequence, completion, &max_error, &rms_error);
  // Ridge bias only (header: about ridge_floor² relative).
  EXPECT_LT(max_error, 1e-6);
  EXPECT_LT(completion.residual_rms, 1e-6);
  EXPECT_TRUE(completion.converged);
  // Visible entries are kept as measured.
  const Measurements& m = sequence.measurements;
  for (int p = 0; p < m.num_points; ++p) {
    if (m.visible(0, p)) {
      EXPECT_EQ(completion.completed(0, p), m.W(0, p));
    }
  }

  // Without the ridge the fit is exact to round-off.
  options.ridge_floor = 0.0;
  ASSERT_TRUE(
      CompleteLowRankAffine(sequence.measurements, rank, options, &completion)
          .ok());
  MissingErrors(sequence, completion, &max_error, &rms_error);
  EXPECT_LT(max_error, 1e-9);
}

TEST(LowRankCompletion, NoisyCompletionStaysAtTheNoiseLevel) {
  const double noise = 0.01;
  const SyntheticSequence sequence = RandomMissing(2, noise, 0.3);
  LowRankCompletionOptions options;
  int rank = 6;
  LowRankCompletion completion;
  ASSERT_TRUE(
      CompleteLowRankAffine(sequence.measurements, rank, options, &completion)
          .ok());
  double max_error = 0.0, rms_error = 0.0;
  MissingErrors(sequence, completion, &max_error, &rms_error);
  // A 2D point with noise σ per coordinate is off by σ√2 RMS; the completed
  // entries are predictions from 2 · 28 observations per row and ~170 per
  // column, so their error is below the noise of one observation.
  EXPECT_LT(rms_error, noise * std::sqrt(2.0));
  // The fit residual is the noise minus the fitted degrees of freedom.
  EXPECT_GT(completion.residual_rms, 0.5 * noise * std::sqrt(2.0));
  EXPECT_LT(completion.residual_rms, noise * std::sqrt(2.0));
}

TEST(LowRankCompletion, TranslationOfACompleteViewIsItsMean) {
  SyntheticSequence sequence = RandomMissing(2, 0.0, 0.0);
  Measurements& m = sequence.measurements;
  m.visible(3, 7) = false;  // one incomplete view; all others complete
  LowRankCompletionOptions options;
  int rank = 6;
  LowRankCompletion completion;
  ASSERT_TRUE(CompleteLowRankAffine(m, rank, options, &completion).ok());
  EXPECT_DOUBLE_EQ(completion.translations(0), m.W.row(0).mean());
  EXPECT_DOUBLE_EQ(completion.translations(1), m.W.row(1).mean());
  // The hidden entry is predicted (noise-free, exact up to the ridge bias).
  const Eigen::Vector2d truth = sequence.truth.Project(3, 0).col(7);
  EXPECT_LT((completion.completed.block<2, 1>(6, 7) - truth).norm(), 1e-6);
}

TEST(LowRankCompletion, UnderdeterminedRowsAndColumnsAreErrors) {
  SyntheticSequence sequence = RandomMissing(2, 0.0, 0.0);
  LowRankCompletionOptions options;
  int rank = 6;
  LowRankCompletion completion;

  Measurements few_points = sequence.measurements;
  few_points.visible.row(4).setConstant(false);
  few_points.visible.row(4).head(6).setConstant(true);  // 6 < r + 1 = 7
  Status status = CompleteLowRankAffine(few_points, rank, options, &completion);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("frame 4 sees 6 points"), std::string::npos)
      << status.message();

  Measurements few_views = sequence.measurements;
  few_views.visible.col(11).setConstant(false);
  few_views.visible.col(11).head(2).setConstant(true);  // 2 views < ⌈6/2⌉
  status = CompleteLowRankAffine(few_views, rank, options, &completion);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("point 11 is seen in 2 views"),
            std::string::npos)
      << status.message();

  rank = 0;
  EXPECT_FALSE(
      CompleteLowRankAffine(sequence.measurements, rank, options, &completion)
          .ok());
}

}  // namespace
}  // namespace nrsfm
