// Hand-computed values of the measurements behind the prior rule
// (solvers/pipeline/prior_rule.h), the decisions they lead to, and
// Reconstruct()'s use of them.
#include "solvers/pipeline/prior_rule.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "core/math/rotation.h"
#include "core/synthetic/synthetic.h"
#include "solvers/pipeline/reconstruct.h"

namespace nrsfm {
namespace {

// Two points at (±1, 0) in every frame, shifted right by `step` per frame:
// spread 1, frame-to-frame motion `step` for every point.
Measurements Translating(int frames, double step) {
  Eigen::MatrixXd w(2 * frames, 2);
  for (int t = 0; t < frames; ++t) {
    w.block<2, 2>(2 * t, 0) << -1 + step * t, 1 + step * t, 0, 0;
  }
  Measurements m;
  EXPECT_TRUE(Measurements::FromMatrixWithNaN(w, 1, "test", &m).ok());
  return m;
}

Model PathModel(const std::vector<double>& angles_deg) {
  Model model;
  model.Resize(static_cast<int>(angles_deg.size()), 1, 4, 1);
  for (int t = 0; t < model.num_frames; ++t) {
    model.SetRotation(t, 0,
                      AngleAxisToRotation(
                          Eigen::Vector3d(0, angles_deg[t] * M_PI / 180.0, 0)));
  }
  return model;
}

TEST(PriorRule, TrackStepIsTheMedianMotionOverTheSpread) {
  EXPECT_NEAR(MedianTrackStep(Translating(5, 0.1)), 0.1, 1e-12);
  EXPECT_NEAR(MedianTrackStep(Translating(5, 0.5)), 0.5, 1e-12);
  EXPECT_NEAR(MedianTrackStep(Translating(5, 0.1), 3), 0.3, 1e-12);
  // One frame: no pair.
  EXPECT_EQ(MedianTrackStep(Translating(1, 0.1)), -1.0);
}

// Frames in time order move further at longer lags; the same positions in
// no order do not.
TEST(PriorRule, TrackOrderGrowsWithTheLagOnlyForOrderedFrames) {
  // Steady motion over 16 frames: m_L = L m_1 up to L = F / 2 = 8.
  EXPECT_NEAR(TrackOrder(Translating(16, 0.01)), 8.0, 1e-9);
  // Shifts t·φ mod 1 (φ the golden ratio): equidistributed, no order.
  const int frames = 64;
  Eigen::MatrixXd w(2 * frames, 2);
  for (int t = 0; t < frames; ++t) {
    const double shift = std::fmod(t * 0.6180339887498949, 1.0);
    w.block<2, 2>(2 * t, 0) << -1 + shift, 1 + shift, 0, 0;
  }
  Measurements unordered;
  ASSERT_TRUE(Measurements::FromMatrixWithNaN(w, 1, "test", &unordered).ok());
  const double order = TrackOrder(unordered);
  EXPECT_GT(order, 0.0);
  EXPECT_LT(order, PriorRuleOptions().min_track_order) << order;
  EXPECT_EQ(TrackOrder(Translating(7, 0.01)), -1.0);  // F < 8
}

TEST(PriorRule, TrackStepSkipsPointsMissingInEitherFrame) {
  Measurements m = Translating(3, 0.2);
  // Point 1 missing in frame 1: pairs (0,1) and (1,2) use point 0 only; the
  // spread is still 1 in frames 0 and 2 and 0 in frame 1 (one point), so
  // spread = sqrt((1 + 1 + 1 + 1) / 5) over the five visible observations.
  m.visible(1, 1) = false;
  const double spread = std::sqrt(4.0 / 5.0);
  EXPECT_NEAR(m.ImageSpreadRms(), spread, 1e-12);
  EXPECT_NEAR(MedianTrackStep(m), 0.2 / spread, 1e-12);
}

TEST(PriorRule, PathAccelerationOfConstantAndAcceleratingPaths) {
  // Constant 5 degrees per frame: no acceleration.
  EXPECT_NEAR(MedianPathAccelerationDeg(PathModel({0, 5, 10, 15, 20})), 0.0,
              1e-9);
  // Steps 1, 2, 3, 4 degrees: acceleration 1 degree per frame² everywhere.
  EXPECT_NEAR(MedianPathAccelerationDeg(PathModel({0, 1, 3, 6, 10})), 1.0,
              1e-9);
  EXPECT_EQ(MedianPathAccelerationDeg(PathModel({0, 1})), -1.0);
  EXPECT_EQ(MedianPathAccelerationDeg(PathModel({0, 1, 3, 6}), 2),
            -1.0);  // F < 2L + 1
  // θ_t = t²/2: a_L = 1 at every lag, so a_4 − a_1 / 16 = 15 / 16.
  std::vector<double> accelerating, jittered;
  for (int t = 0; t < 12; ++t) {
    accelerating.push_back(0.5 * t * t);
    // A constant 5°/frame with ±0.5° jitter: a_1 = 2 from the jitter alone,
    // a_4 = 0 (the jitter repeats every 2 frames), so no acceleration.
    jittered.push_back(5.0 * t + (t % 2 == 0 ? 0.5 : -0.5));
  }
  EXPECT_NEAR(PathAccelerationDeg(PathModel(accelerating)), 15.0 / 16.0, 1e-9);
  EXPECT_NEAR(MedianPathAccelerationDeg(PathModel(jittered)), 2.0, 1e-9);
  EXPECT_NEAR(PathAccelerationDeg(PathModel(jittered)), 0.0, 1e-9);
  EXPECT_EQ(PathAccelerationDeg(PathModel({0, 1, 2, 3, 4, 5, 6, 7})),
            -1.0);  // F < 9
}

TEST(PriorRule, LargestViewAngle) {
  EXPECT_NEAR(LargestViewAngleDeg(PathModel({0, 10, 40, 25})), 40.0, 1e-6);
  EXPECT_NEAR(LargestViewAngleDeg(PathModel({-30, 10, 20})), 50.0, 1e-6);
}

TEST(PriorRule, DecisionsFollowTheThresholds) {
  // The path threshold at 0.1 °/frame², between the constant path (0) and the
  // shaking one (about 0.5 · 0.25 · 2 °/frame² at its peaks).
  PriorRuleOptions options;
  options.max_path_acceleration_deg = 0.1;
  PriorDecision video;
  // P = 2 points, K = 1: 3K ≥ P / 2.
  ASSERT_TRUE(DecidePriors(options, Translating(12, 0.05), 1, &video).ok());
  EXPECT_TRUE(video.video);
  EXPECT_EQ(video.term_weights.at("temporal_shape"),
            options.temporal_shape_weight);

  std::vector<double> constant, shaking;
  for (int t = 0; t < 12; ++t) {
    constant.push_back(5.0 * t);
    shaking.push_back(5.0 * t +
                      2.0 * std::sin(0.5 * t));  // a real, varying path
  }
  PriorDecision smooth = video;
  DecideStartPriors(options, PathModel(constant), PathModel(constant), 1.0,
                    &smooth);
  EXPECT_EQ(smooth.term_weights.at("rotation_acceleration"),
            options.rotation_acceleration_weight);

  PriorDecision shaky = video;
  DecideStartPriors(options, PathModel(shaking), PathModel(shaking), 1.0,
                    &shaky);
  EXPECT_GT(shaky.path_acceleration_deg, options.max_path_acceleration_deg);
  EXPECT_EQ(shaky.term_weights.count("rotation_acceleration"), 0u);

  // The threshold decides: 0 never adds the term, not even for the constant
  // path; one above the shaking path's acceleration adds it there too.
  PriorRuleOptions never = options;
  never.max_path_acceleration_deg = 0.0;
  PriorDecision smooth_never = video;
  DecideStartPriors(never, PathModel(constant), PathModel(constant), 1.0,
                    &smooth_never);
  EXPECT_EQ(smooth_never.term_weights.count("rotation_acceleration"), 0u);
  PriorRuleOptions lenient = options;
  lenient.max_path_acceleration_deg = 2.0 * shaky.path_acceleration_deg;
  PriorDecision shaky_lenient = video;
  DecideStartPriors(lenient, PathModel(shaking), PathModel(shaking), 1.0,
                    &shaky_lenient);
  EXPECT_EQ(shaky_lenient.term_weights.count("rotation_acceleration"), 1u);

  // Frames in no order get the deformation prior instead of a temporal
  // term, and no path prior after.
  PriorDecision unordered;
  ASSERT_TRUE(DecidePriors(options, Translating(7, 0.05), 1, &unordered)
                  .ok());  // too short to tell
  EXPECT_FALSE(unordered.video);
  DecideStartPriors(options, PathModel(constant), PathModel(constant), 1.0,
                    &unordered);
  ASSERT_EQ(unordered.term_weights.size(), 1u);
  EXPECT_EQ(unordered.term_weights.at("deformation"),
            options.deformation_weight);
  EXPECT_EQ(unordered.path_acceleration_deg, -1.0);
}

TEST(PriorRule, NoTermOnlyForExactLowRankTracksThatFixTheRotations) {
  // 40 points, K = 6: 3K = 18 < 0.5 · 40, the rotations are fixed by the
  // data, and the tracks (rank 2 after centring) are explained exactly; a
  // video all the same, but no term and no path prior.
  Eigen::MatrixXd w(2 * 12, 40);
  for (int t = 0; t < 12; ++t) {
    for (int p = 0; p < 40; ++p) {
      w(2 * t, p) = std::cos(p) + 0.01 * t;
      w(2 * t + 1, p) = std::sin(p);
    }
  }
  Measurements m;
  ASSERT_TRUE(Measurements::FromMatrixWithNaN(w, 1, "test", &m).ok());
  const PriorRuleOptions options;
  PriorDecision decision;
  ASSERT_TRUE(DecidePriors(options, m, 6, &decision).ok());
  EXPECT_TRUE(decision.video);
  EXPECT_TRUE(decision.model_explains_tracks);
  EXPECT_EQ(decision.camera_num_bases, 6);
  EXPECT_TRUE(decision.term_weights.empty());
  EXPECT_TRUE(decision.exactly_low_rank);
  const Model path = PathModel({0, 5, 10, 15, 20, 25});
  DecideStartPriors(options, path, path, 1.0, &decision);
  EXPECT_TRUE(decision.term_weights.empty());
  // K = 7: 3K = 21 ≥ 20.
  ASSERT_TRUE(DecidePriors(options, m, 7, &decision).ok());
  EXPECT_EQ(decision.term_weights.count("temporal_shape"), 1u);
  // A lower min_basis_fraction moves the threshold: K = 6, 3K = 18 ≥ 0.4 · 40;
  // the term gets temporal_shape_weight.
  PriorRuleOptions lower = options;
  lower.min_basis_fraction = 0.4;
  lower.temporal_shape_weight = 2.5;
  PriorDecision lowered;
  ASSERT_TRUE(DecidePriors(lower, m, 6, &lowered).ok());
  EXPECT_EQ(lowered.term_weights.at("temporal_shape"), 2.5);
}

// The same tracks with noise of 10⁻³ of their spread are no longer exactly
// of low rank: the shape prior is on, at K = 6 too.
TEST(PriorRule, NoisyTracksAlwaysGetTheShapePrior) {
  Eigen::MatrixXd w(2 * 12, 40);
  std::mt19937 random(5);
  std::normal_distribution<double> noise(0.0, 1e-3);
  for (int t = 0; t < 12; ++t) {
    for (int p = 0; p < 40; ++p) {
      w(2 * t, p) = std::cos(p) + 0.01 * t + noise(random);
      w(2 * t + 1, p) = std::sin(p) + noise(random);
    }
  }
  Measurements m;
  ASSERT_TRUE(Measurements::FromMatrixWithNaN(w, 1, "test", &m).ok());
  PriorDecision decision;
  ASSERT_TRUE(DecidePriors(PriorRuleOptions(), m, 6, &decision).ok());
  EXPECT_FALSE(decision.exactly_low_rank);
  EXPECT_EQ(decision.term_weights.count("temporal_shape"), 1u);
}

// K = 2, basis 1 fixed (weight 1), basis 2 of squared norm g: with weights
// l_t2 = 0, 1, 2, 3 the deviations from the mean (−1.5 … 1.5) sum to 5g,
// the changes to 3g, so c = 1 − 3g / (2 · 3/4 · 5g) = 0.6; with ±1
// alternating, 4g and 12g: 1 − 12 / 6 = −1, clamped to 0.
Model TwoBasisModel(const std::vector<double>& second_weights) {
  Model model;
  model.Resize(static_cast<int>(second_weights.size()), 1, 3, 2);
  model.basis.setZero();
  model.basis.topRows(3) << 1, 0, -1, 0, 1, 0, 0, 0, 1;
  model.basis.bottomRows(3) << 0.5, -0.5, 0, 0, 0, 2, 1, 0, 0;
  for (int t = 0; t < model.num_frames; ++t) {
    model.weights(0, t) = 1.0;
    model.weights(1, t) = second_weights[t];
  }
  return model;
}

TEST(PriorRule, DeformationCoherenceByHand) {
  EXPECT_NEAR(DeformationCoherence(TwoBasisModel({0, 1, 2, 3})), 0.6, 1e-12);
  EXPECT_EQ(DeformationCoherence(TwoBasisModel({1, -1, 1, -1})), 0.0);
  EXPECT_EQ(DeformationCoherence(TwoBasisModel({2, 2, 2})), 1.0);  // rigid
  EXPECT_EQ(DeformationCoherence(TwoBasisModel({2})), -1.0);       // F < 2
}

TEST(PriorRule, TheAlternativeTemporalShapeWeightFollowsTheCoherence) {
  PriorRuleOptions options;
  options.max_path_acceleration_deg = 0.0;  // no path prior here
  PriorDecision decision;
  decision.video = true;
  decision.term_weights["temporal_shape"] = options.temporal_shape_weight;
  PriorDecision smooth = decision, alternating = decision, strong = decision;
  const Model ramp = TwoBasisModel({0, 1, 2, 3});
  DecideStartPriors(options, ramp, ramp, 1.0, &smooth);
  // The full weight stays the candidate; the alternative is
  // 1 · (10⁻⁴)^(0.4⁴) = 10^(−0.1024) = 0.78995.
  EXPECT_EQ(smooth.term_weights.at("temporal_shape"),
            options.temporal_shape_weight);
  EXPECT_NEAR(smooth.temporal_shape_alternative, 0.78995, 1e-5);
  EXPECT_NEAR(smooth.deformation_coherence, 0.6, 1e-12);
  const Model flip = TwoBasisModel({1, -1, 1, -1});
  DecideStartPriors(options, flip, flip, 1.0, &alternating);
  EXPECT_NEAR(alternating.temporal_shape_alternative,
              options.min_temporal_shape_weight, 1e-15);
  // A repair's strength multiplies both.
  DecideStartPriors(options, ramp, ramp, 10.0, &strong);
  EXPECT_EQ(strong.term_weights.at("temporal_shape"),
            10.0 * options.temporal_shape_weight);
  EXPECT_NEAR(strong.temporal_shape_alternative, 7.8995, 1e-4);
}

// Tracks x = a + b t + c t² per coordinate have third differences 0; white
// noise of σ adds 20 σ² to their variance, which the estimate reads back.
TEST(PriorRule, TemporalNoiseRmsReadsTheNoiseOfSmoothTracks) {
  constexpr int kFrames = 200, kPoints = 20;
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd smooth(2 * kFrames, kPoints), noise(2 * kFrames, kPoints);
  for (int t = 0; t < kFrames; ++t) {
    for (int p = 0; p < kPoints; ++p) {
      for (int row = 0; row < 2; ++row) {
        const double u = 0.01 * t;
        smooth(2 * t + row, p) = p + row + (0.3 + 0.01 * p) * u - 0.2 * u * u;
        noise(2 * t + row, p) = normal(rng);
      }
    }
  }
  Measurements exact, noisy;
  ASSERT_TRUE(
      Measurements::FromMatrixWithNaN(smooth, 1, "smooth", &exact).ok());
  ASSERT_TRUE(
      Measurements::FromMatrixWithNaN(smooth + 0.01 * noise, 1, "noisy", &noisy)
          .ok());
  EXPECT_LT(TemporalNoiseRms(exact), 1e-12);
  // 7 880 differences: the median's standard error is ~1.5 %.
  EXPECT_NEAR(TemporalNoiseRms(noisy), 0.01, 0.0006);
  // Fewer than four frames: nothing to measure.
  ASSERT_TRUE(
      Measurements::FromMatrixWithNaN(smooth.topRows(6), 1, "short", &exact)
          .ok());
  EXPECT_EQ(TemporalNoiseRms(exact), -1.0);
}

// Tracks of exactly K0 = 3 random basis shapes (new weights every frame, a
// smoothly turning camera): rank 3K0 explains them, so K = 3 needs no camera
// stage. With the spectrum's noise estimate (frames in no order) K = 2 does
// not, and its camera is estimated with the 3 bases that do; with 1 % noise
// the same, and the estimate reads the noise. Read as a video, the third
// differences count a deformation that jumps from frame to frame as noise,
// so K = 2 explains what is left as well (no camera stage: nothing in these
// tracks is smooth enough for a temporal prior to use).
TEST(PriorRule, TrackRankFindsTheBasesThatExplainTheTracks) {
  for (const double noise : {0.0, 0.01}) {
    RandomBasisOptions data;
    data.num_frames = 120;
    data.num_points = 40;
    data.num_bases = 3;
    data.noise_stddev = noise;
    SyntheticSequence s;
    ASSERT_TRUE(GenerateRandomBasis(data, &s).ok());
    for (const bool video : {false, true}) {
      SCOPED_TRACE(::testing::Message()
                   << "noise " << noise << ", video " << video);
      PriorDecision three;
      ASSERT_TRUE(
          AnalyseTrackRank(PriorRuleOptions(), s.measurements, 3, video, &three)
              .ok());
      EXPECT_TRUE(three.model_explains_tracks);
      EXPECT_EQ(three.camera_num_bases, 3);
      PriorDecision two;
      ASSERT_TRUE(
          AnalyseTrackRank(PriorRuleOptions(), s.measurements, 2, video, &two)
              .ok());
      EXPECT_EQ(two.model_explains_tracks, video);
      EXPECT_EQ(two.camera_num_bases, video ? 2 : 3);
      if (noise > 0.0 && !video) {
        EXPECT_NEAR(two.noise_rms, noise, 0.2 * noise);
      }
    }
  }
}

// Smooth tracks of full rank (400 frames of slow sinusoids with slowly
// decaying amplitudes over 24 points): their third differences read almost
// no noise, no small basis explains them, and the camera stage takes the
// cap, 3K' ≤ camera_rank_fraction · min(P, 2F). (With the spectrum's noise
// estimate instead, the rank it is read at, 3 · min(P, 2F) / 6, explains the
// tracks by construction, so the cap binds only for videos.)
TEST(PriorRule, CameraBasesStopAtTheCap) {
  constexpr int kFrames = 400, kPoints = 24;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> phase(0.0, 2.0 * M_PI);
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(2 * kFrames, kPoints);
  for (int i = 0; i < 30; ++i) {
    const double amplitude = std::pow(0.9, i), frequency = 0.01 + 0.004 * i;
    for (int p = 0; p < kPoints; ++p) {
      for (int row = 0; row < 2; ++row) {
        const double offset = phase(rng);
        for (int t = 0; t < kFrames; ++t) {
          w(2 * t + row, p) += amplitude * std::cos(frequency * t + offset);
        }
      }
    }
  }
  Measurements m;
  ASSERT_TRUE(Measurements::FromMatrixWithNaN(w, 1, "smooth", &m).ok());
  PriorRuleOptions options;
  PriorDecision decision;
  ASSERT_TRUE(AnalyseTrackRank(options, m, 1, /*video=*/true, &decision).ok());
  EXPECT_FALSE(decision.model_explains_tracks);
  EXPECT_EQ(decision.camera_num_bases, 6);  // 0.75 · 24 / 3
  options.camera_rank_fraction = 0.5;
  ASSERT_TRUE(AnalyseTrackRank(options, m, 1, /*video=*/true, &decision).ok());
  EXPECT_EQ(decision.camera_num_bases, 4);
  // K at the cap: no larger camera model.
  ASSERT_TRUE(AnalyseTrackRank(options, m, 4, /*video=*/true, &decision).ok());
  EXPECT_EQ(decision.camera_num_bases, 4);
}

TEST(PriorRule, OptionsAreChecked) {
  PriorRuleOptions options;
  options.min_track_order = 1.0;
  EXPECT_NE(options.Check().message().find("min_track_order"),
            std::string::npos);
  options = PriorRuleOptions();
  options.rotation_acceleration_weight = NAN;
  EXPECT_NE(options.Check().message().find("rotation_acceleration_weight"),
            std::string::npos);
  options = PriorRuleOptions();
  options.min_basis_fraction = 0.0;
  EXPECT_NE(options.Check().message().find("min_basis_fraction"),
            std::string::npos);
  options = PriorRuleOptions();
  options.deformation_weight = 0.0;
  EXPECT_NE(options.Check().message().find("deformation_weight"),
            std::string::npos);
  options = PriorRuleOptions();
  options.camera_rank_fraction = 1.0;
  EXPECT_NE(options.Check().message().find("camera_rank_fraction"),
            std::string::npos);
  options = PriorRuleOptions();
  options.camera_fit_threshold = 0.9;
  EXPECT_NE(options.Check().message().find("camera_fit_threshold"),
            std::string::npos);
  options = PriorRuleOptions();
  options.camera_function_tolerance = 0.0;
  EXPECT_NE(options.Check().message().find("camera_function_tolerance"),
            std::string::npos);
  options = PriorRuleOptions();
  options.temporal_shape_weight = -1.0;
  EXPECT_NE(options.Check().message().find("temporal_shape_weight"),
            std::string::npos);
  options = PriorRuleOptions();
  options.max_path_acceleration_deg = -0.1;
  EXPECT_NE(options.Check().message().find("max_path_acceleration_deg"),
            std::string::npos);
  EXPECT_TRUE(PriorRuleOptions().Check().ok());
}

TEST(PriorRule, WeightsGivenWithAutoPriorsAreAnError) {
  ReconstructOptions options;
  options.problem.term_weights["temporal_shape"] = 1.0;
  const Status status = options.Check();
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("priors = manual"), std::string::npos)
      << status.message();
  options.priors = PriorMode::kManual;
  EXPECT_TRUE(options.Check().ok());
}

}  // namespace
}  // namespace nrsfm
