// Points and frames with too few observations
// (solvers/pipeline/drop_unobserved.h): the rule, the index bookkeeping, and
// Reconstruct() leaving them out.
#include "solvers/pipeline/drop_unobserved.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/eval/metrics.h"
#include "core/synthetic/synthetic.h"
#include "solvers/pipeline/reconstruct.h"

namespace nrsfm {
namespace {

SyntheticSequence Sequence(int frames, int points, int bases,
                           double missing = 0.0, int cameras = 1) {
  SyntheticSequence sequence;
  if (cameras == 1) {
    RandomBasisOptions options;
    options.num_frames = frames;
    options.num_points = points;
    options.num_bases = bases;
    options.missing_fraction = missing;
    options.seed = 3;
    EXPECT_TRUE(GenerateRandomBasis(options, &sequence).ok());
  } else {
    ShoeOptions options;
    options.num_frames = frames;
    options.num_points = points;
    options.num_cameras = cameras;
    options.seed = 3;
    EXPECT_TRUE(GenerateShoe(options, &sequence).ok());
  }
  return sequence;
}

void Hide(Measurements* m, int view, int point) {
  m->visible(view, point) = false;
  m->W.block<2, 1>(2 * view, point).setConstant(NAN);
}

TEST(FindUnobserved, PointsAndFramesBelowWhatTheModelNeeds) {
  // K = 2: a point's 6 basis parameters need 3 views, a view's pose and the
  // frame's weights 4 points.
  EXPECT_EQ(MinViewsPerPoint(2), 3);
  EXPECT_EQ(MinPointsPerView(2), 4);
  Measurements m = Sequence(20, 12, 2).measurements;
  Unobserved unobserved;
  ASSERT_TRUE(FindUnobserved(m, 2, &unobserved).ok());
  EXPECT_TRUE(unobserved.empty());  // complete: nothing

  Hide(&m, 3, 2);  // point 2 misses one frame: kept
  for (int t = 1; t < 20; ++t) Hide(&m, t, 4);  // point 4 in frame 0 only
  for (int t = 0; t < 20; ++t) Hide(&m, t, 9);  // point 9 nowhere
  for (int p = 0; p < 9; ++p)
    Hide(&m, 5, p);  // frame 5 sees 10, 11 of the kept
  for (int p = 0; p < 7; ++p)
    Hide(&m, 6, p);  // frame 6 sees 4 of the kept: enough
  ASSERT_TRUE(FindUnobserved(m, 2, &unobserved).ok());
  EXPECT_EQ(unobserved.num_bases, 2);
  EXPECT_EQ(unobserved.points, (std::vector<int>{4, 9}));
  EXPECT_EQ(unobserved.frames, (std::vector<int>{5}));

  const std::string warning = UnobservedWarning(m, unobserved);
  EXPECT_EQ(warning,
            "left out of the reconstruction (K = 2 needs every point seen in "
            "at least 3 "
            "views and every frame's views to see at least 4 points), NaN in "
            "the result: "
            "point 4 (seen in 1 view), point 9 (seen in 0 views); frame 5 "
            "(sees 2 points of those kept)");
}

// The thresholds grow with K: 2K·… equations for 3K basis unknowns per
// point, 2 per point seen for the view's pose and the frame's K weights.
TEST(FindUnobserved, ThresholdsAreWhatKBasesNeed) {
  EXPECT_EQ(MinViewsPerPoint(1), 2);
  EXPECT_EQ(MinViewsPerPoint(3), 5);  // 2 · 5 = 10 >= 9
  EXPECT_EQ(MinViewsPerPoint(4), 6);  // 2 · 6 = 12 >= 12
  EXPECT_EQ(MinViewsPerPoint(12), 18);
  EXPECT_EQ(MinPointsPerView(1), 4);
  EXPECT_EQ(MinPointsPerView(4), 5);   // 2 · 5 = 10 >= 4 + 5
  EXPECT_EQ(MinPointsPerView(12), 9);  // 2 · 9 = 18 >= 12 + 5
  // A point seen in 5 views is kept at K = 3 and left out at K = 4 (the
  // shoe of seed 7: keeping it made the whole start drop to K' = 3).
  Measurements m = Sequence(20, 16, 1).measurements;
  for (int t = 5; t < 20; ++t) Hide(&m, t, 11);
  Unobserved unobserved;
  ASSERT_TRUE(FindUnobserved(m, 3, &unobserved).ok());
  EXPECT_TRUE(unobserved.empty());
  ASSERT_TRUE(FindUnobserved(m, 4, &unobserved).ok());
  EXPECT_EQ(unobserved.points, (std::vector<int>{11}));
  EXPECT_TRUE(unobserved.frames.empty());
}

TEST(FindUnobserved, LeavingOutCascadesUntilNothingChanges) {
  // K = 1: 4 points per view, 2 views per point. Frame 3 sees points 0-3
  // only; point 3 is seen in frames 3 and 4 only; point 10 is seen nowhere.
  // Leaving out point 10 changes no other count, so only point 10 goes.
  Measurements m = Sequence(8, 11, 1).measurements;
  for (int p = 4; p < 11; ++p) Hide(&m, 3, p);
  for (int t = 0; t < 8; ++t) {
    if (t != 3 && t != 4) Hide(&m, t, 3);
    if (t != 3) Hide(&m, t, 10);
  }
  Unobserved unobserved;
  ASSERT_TRUE(FindUnobserved(m, 1, &unobserved).ok());
  EXPECT_EQ(unobserved.points, (std::vector<int>{10}));
  EXPECT_TRUE(unobserved.frames.empty());
  // Now hide point 2 in frame 3: frame 3 sees 0, 1, 3 (3 < 4 points) and
  // goes; point 3 is then seen in frame 4 alone (1 < 2 views) and goes;
  // frame 4 then sees 4, 5, 6 (3 points) and goes too.
  Hide(&m, 3, 2);
  for (int p = 0; p < 11; ++p) {
    if (p < 3 || p > 6) Hide(&m, 4, p);
  }
  ASSERT_TRUE(FindUnobserved(m, 1, &unobserved).ok());
  EXPECT_EQ(unobserved.points, (std::vector<int>{3, 10}));
  EXPECT_EQ(unobserved.frames, (std::vector<int>{3, 4}));
}

TEST(FindUnobserved, TooLittleLeftIsAnErrorAndTooSmallDataIsLeftToInitialize) {
  Measurements m = Sequence(6, 8, 1).measurements;
  for (int t = 0; t < 5; ++t) Hide(&m, t, 0);  // one view of point 0
  for (int t = 1; t < 6; ++t) {
    for (int p = 1; p < 6; ++p) Hide(&m, t, p);  // frames 1-5 see 3 points
  }
  Unobserved unobserved;
  const Status status = FindUnobserved(m, 1, &unobserved);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("too few observations for K = 1"),
            std::string::npos)
      << status.message();
  // Points 0-5 are seen once, so frame 0 keeps 2 points; then no frame is
  // left and neither are points 6 and 7.
  EXPECT_NE(status.message().find("leaves F = 0, P = 0"), std::string::npos)
      << status.message();
  // P < 3K + 1: nothing is left out, ComputeStart() says what is wrong.
  ASSERT_TRUE(FindUnobserved(m, 3, &unobserved).ok());
  EXPECT_TRUE(unobserved.empty());
}

TEST(FindUnobserved, ExpandModelPutsTheKeptValuesBackAndNaNElsewhere) {
  const SyntheticSequence s = Sequence(10, 12, 2, 0.0, 2);
  Unobserved unobserved;
  unobserved.num_bases = 2;
  unobserved.points = {0, 7};
  unobserved.frames = {4};
  const Measurements kept = WithoutUnobserved(s.measurements, unobserved);
  EXPECT_EQ(kept.num_frames, 9);
  EXPECT_EQ(kept.num_cameras, 2);
  EXPECT_EQ(kept.num_points, 10);
  ASSERT_TRUE(kept.Validate().ok());
  // Frame 5, camera 1, point 8 of the input is frame 4, camera 1, point 6 kept.
  const Eigen::Vector2d kept_w = kept.W.block<2, 1>(kept.Row(4, 1), 6);
  const Eigen::Vector2d input_w =
      s.measurements.W.block<2, 1>(s.measurements.Row(5, 1), 8);
  EXPECT_TRUE(kept_w == input_w ||
              (kept_w.array().isNaN().all() && input_w.array().isNaN().all()));
  EXPECT_EQ(kept.visible(kept.View(4, 1), 6),
            s.measurements.visible(s.measurements.View(5, 1), 8));

  // The truth restricted the same way, expanded again: equal where kept.
  Model small;
  small.Resize(9, 2, 10, s.truth.num_bases);
  for (int t = 0, k = 0; t < 10; ++t) {
    if (t == 4) continue;
    for (int c = 0; c < 2; ++c) {
      small.rotations.col(small.View(k, c)) =
          s.truth.rotations.col(s.truth.View(t, c));
      small.translations.col(small.View(k, c)) =
          s.truth.translations.col(s.truth.View(t, c));
      small.scales(small.View(k, c)) = s.truth.scales(s.truth.View(t, c));
    }
    small.weights.col(k++) = s.truth.weights.col(t);
  }
  for (int p = 0, k = 0; p < 12; ++p) {
    if (p != 0 && p != 7) small.basis.col(k++) = s.truth.basis.col(p);
  }
  small.rig_rotations = s.truth.rig_rotations;
  small.rig_scales = s.truth.rig_scales;
  const Model full = ExpandModel(small, s.measurements, unobserved);
  ASSERT_TRUE(full.Validate(/*allow_nan=*/true).ok());
  EXPECT_FALSE(full.Validate().ok());
  for (int t = 0; t < 10; ++t) {
    for (int c = 0; c < 2; ++c) {
      const Eigen::Matrix2Xd projected = full.Project(t, c);
      for (int p = 0; p < 12; ++p) {
        const bool left_out = t == 4 || p == 0 || p == 7;
        EXPECT_EQ(projected.col(p).array().isNaN().all(), left_out)
            << t << " " << p;
        if (!left_out) {
          EXPECT_LT((projected.col(p) - s.truth.Project(t, c).col(p)).norm(),
                    1e-12);
        }
      }
    }
  }
  EXPECT_TRUE(full.weights.col(4).array().isNaN().all());
  EXPECT_EQ(full.rig_rotations, s.truth.rig_rotations);
}

// Per-observation values (observation weights) follow the observations
// WithoutUnobserved keeps: value 100·view + point of the input lands where
// that observation lands; an array of another size is left as it is.
TEST(FindUnobserved, PerObservationValuesFollowTheKeptObservations) {
  // F = 10, M = 2, P = 12
  const SyntheticSequence s = Sequence(10, 12, 2, 0.0, 2);
  Unobserved unobserved;
  unobserved.num_bases = 2;
  unobserved.points = {0, 7};
  unobserved.frames = {4, 9};
  Eigen::ArrayXXd values(20, 12);
  for (int view = 0; view < 20; ++view) {
    for (int p = 0; p < 12; ++p) values(view, p) = 100 * view + p;
  }
  const Eigen::ArrayXXd kept =
      WithoutUnobserved(values, s.measurements, unobserved);
  const Measurements kept_m = WithoutUnobserved(s.measurements, unobserved);
  ASSERT_EQ(kept.rows(), kept_m.NumViews());  // 8 frames × 2 cameras
  ASSERT_EQ(kept.rows(), 16);
  ASSERT_EQ(kept.cols(), 10);
  // Kept frame 4 is input frame 5; kept point 6 is input point 8; camera 1:
  // input view 5·2 + 1 = 11.
  EXPECT_EQ(kept(kept_m.View(4, 1), 6), 1108.0);
  // Kept frame 7 is input frame 8 (frames 4 and 9 left out); point 0 is 1.
  EXPECT_EQ(kept(kept_m.View(7, 0), 0), 1601.0);
  EXPECT_EQ(kept(0, 0), 1.0);
  EXPECT_EQ(kept(kept_m.View(3, 1), 9),
            711.0);  // input frame 3, camera 1, point 11

  EXPECT_EQ(
      WithoutUnobserved(Eigen::ArrayXXd(), s.measurements, unobserved).size(),
      0);
  const Eigen::ArrayXXd wrong = Eigen::ArrayXXd::Ones(19, 12);
  EXPECT_EQ(WithoutUnobserved(wrong, s.measurements, unobserved).rows(), 19);
}

// Reconstruct() with default options and K bases; a usable refinement.
void ReconstructWithK(const Measurements& m, int num_bases,
                      ReconstructResult* result) {
  ReconstructOptions options;
  options.start.num_bases = num_bases;
  ASSERT_TRUE(Reconstruct(options, m, result).ok());
  ASSERT_TRUE(result->refine.usable) << result->refine.message;
}

// A point seen in a single frame and a frame that sees no point: the rest
// is reconstructed as if they were not there (noise-free: exactly), and the
// two are NaN in the model, listed and named in a warning.
TEST(Reconstruct, LeavesOutAPointSeenOnceAndAFrameThatSeesNothing) {
  SyntheticSequence s = Sequence(60, 20, 2, 0.1);
  Measurements& m = s.measurements;
  for (int t = 1; t < 60; ++t) Hide(&m, t, 6);   // point 6: frame 0 only
  for (int p = 0; p < 20; ++p) Hide(&m, 17, p);  // frame 17: nothing
  ReconstructResult result;
  ASSERT_NO_FATAL_FAILURE(ReconstructWithK(m, 2, &result));
  EXPECT_EQ(result.dropped_points, (std::vector<int>{6}));
  EXPECT_EQ(result.dropped_frames, (std::vector<int>{17}));
  ASSERT_FALSE(result.warnings.empty());
  EXPECT_NE(result.warnings[0].find(
                "point 6 (seen in 1 view); frame 17 (sees 0 points"),
            std::string::npos)
      << result.warnings[0];
  const Model& model = result.model;
  EXPECT_EQ(model.num_frames, 60);
  EXPECT_EQ(model.num_points, 20);
  EXPECT_TRUE(model.basis.col(6).array().isNaN().all());
  EXPECT_TRUE(model.rotations.col(17).array().isNaN().all());
  EXPECT_TRUE(model.weights.col(17).array().isNaN().all());
  EXPECT_TRUE(model.Validate(/*allow_nan=*/true).ok());

  // Scored against the truth, the left-out frame and point are not counted
  // and the rest is exact.
  ShapeErrors errors;
  ASSERT_TRUE(
      EvaluateShapes(ShapesOfModel(s.truth), ShapesOfModel(model), &errors)
          .ok());
  EXPECT_EQ(errors.unscored_points, (std::vector<int>{6}));
  EXPECT_EQ(errors.unscored_frames, (std::vector<int>{17}));
  EXPECT_EQ(errors.num_frames, 60);
  EXPECT_EQ(errors.num_points, 20);
  std::printf(
      "left out point 6 and frame 17: e3D %.2e (object frame %.2e), "
      "reprojection "
      "RMS %.2e\n",
      errors.e3d_camera, errors.e3d, result.refine.reprojection_rms);
  EXPECT_LT(errors.e3d_camera, 1e-4);
  EXPECT_LT(result.refine.reprojection_rms, 1e-6);
}

// Options that index the input's observations and frames follow what is
// kept: observation weights of the input's size (the reduced problem
// refused them as the wrong size before) and a smoothness reference frame
// after the left-out frame (input frame 59 is kept frame 58; before, the
// reduced problem had no frame 59).
TEST(Reconstruct, ObservationWeightsAndReferenceFrameFollowTheKeptFrames) {
  SyntheticSequence s = Sequence(60, 20, 2, 0.1);
  Measurements& m = s.measurements;
  for (int p = 0; p < 20; ++p) Hide(&m, 17, p);  // frame 17: nothing, left out
  ReconstructOptions options;
  options.start.num_bases = 2;
  options.priors = PriorMode::kManual;
  options.problem.term_weights = {{"smoothness", 1e-6}};
  options.problem.smoothness_edges.reference_frame = 59;
  options.problem.observation_weights = Eigen::ArrayXXd::Ones(60, 20);
  options.solver.max_iterations = 5;  // 5 steps show it
  ReconstructResult weighted;
  ASSERT_TRUE(Reconstruct(options, m, &weighted).ok());
  ASSERT_TRUE(weighted.refine.usable) << weighted.refine.message;
  EXPECT_EQ(weighted.dropped_frames, (std::vector<int>{17}));
  ReconstructResult plain;
  options.problem.observation_weights = Eigen::ArrayXXd();
  ASSERT_TRUE(Reconstruct(options, m, &plain).ok());
  // Unit weights are no weights: the same refinement.
  EXPECT_NEAR(weighted.refine.final_cost, plain.refine.final_cost,
              1e-9 * plain.refine.initial_cost);
  EXPECT_LT(weighted.refine.final_cost, 0.1 * weighted.refine.initial_cost);
}

// A point seen in too few views for K bases is left out rather than lowering
// the whole start to fewer bases: K = 3 needs 5 views per point; point 5 is
// seen in 4. The start keeps all 3 bases (no "fewer bases" warning) and the
// rest is exact.
TEST(Reconstruct, APointSeenTooRarelyForKIsLeftOutAndTheStartKeepsK) {
  SyntheticSequence s = Sequence(40, 20, 3, 0.05);
  Measurements& m = s.measurements;
  for (int t = 4; t < 40; ++t) Hide(&m, t, 5);
  for (int t = 0; t < 4; ++t) {
    m.visible(t, 5) = true;
    m.W.block<2, 1>(2 * t, 5) = s.truth.Project(t, 0).col(5);
  }
  ReconstructResult result;
  ASSERT_NO_FATAL_FAILURE(ReconstructWithK(m, 3, &result));
  EXPECT_EQ(result.dropped_points, (std::vector<int>{5}));
  EXPECT_TRUE(result.dropped_frames.empty());
  for (const std::string& warning : result.start.warnings) {
    EXPECT_EQ(warning.find("allow a start with at most"), std::string::npos)
        << warning;
  }
  ShapeErrors errors;
  ASSERT_TRUE(EvaluateShapes(ShapesOfModel(s.truth),
                             ShapesOfModel(result.model), &errors)
                  .ok());
  EXPECT_EQ(errors.unscored_points, (std::vector<int>{5}));
  EXPECT_LT(errors.e3d_camera, 1e-4);
}

}  // namespace
}  // namespace nrsfm
