// Drives the real `nrsfm` binary on the real sequences with ground truth
// (../shared/datasets) with default options: the accuracy of the default
// pipeline, scored as the field scores each sequence, with bounds a few
// per cent above what was measured (docs/reliability.md).

#include <gtest/gtest.h>

#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/test_util.h"
#include "tests/tools/cli_test.h"

namespace nrsfm {
namespace {

// Real motion capture (../shared/datasets/yoga.mat, 307 frames): the
// corrective-triple start and the object-frame temporal shape prior, scored
// by the field's protocol (object frame against the world-frame S).
// Measured: e3D 0.1127 (object frame), 0.0243 in the camera frame.
// The default pipeline with no flag but K, scored as the field scores yoga
// (object frame against the world S; docs/metrics.md). The prior rule must
// find a video with 3K near P and a constant-velocity camera and say so.
TEST_F(CliTest, YogaWithDefaultOptions) {
  NRSFM_SKIP_WITHOUT_SHARED_DATA(dir);
  // 45 s in the release build; the sanitizer build runs the same code paths
  // (structured solver, prior rule) on the smaller tests.
  if (testing_util::kSanitizedBuild)
    GTEST_SKIP() << "accuracy run: release build only";
  const std::string yoga = dir + "/yoga.mat";
  const RunResult r = Run("reconstruct --input " + yoga +
                          " --K 10 --output y --truth " + yoga + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const nlohmann::json result =
      nlohmann::json::parse(ReadFile(Path("y/result.json")));
  EXPECT_EQ(result["start_used"], "triple");
  EXPECT_EQ(result["options"]["priors"], "auto");
  // λ = (10⁻⁴)^((1 − c)⁴) with the start's coherence c = 0.998: 1 − 10⁻¹⁰.
  EXPECT_NEAR(result["term_weights"]["temporal_shape"].get<double>(), 1.0,
              1e-6);
  EXPECT_GT(result["diagnostics"]["deformation_coherence"].get<double>(), 0.99);
  EXPECT_EQ(result["term_weights"]["rotation_acceleration"].get<double>(), 1e6);
  // The path prior kept: measured 1.08 (with it over without it).
  EXPECT_LT(result["diagnostics"]["prior_fit_ratio"].get<double>(), 1.2);
  EXPECT_LT(result["diagnostics"]["track_step"].get<double>(), 0.1);
  EXPECT_LT(result["diagnostics"]["path_acceleration_deg"].get<double>(), 0.05);
  EXPECT_GT(result["diagnostics"]["largest_view_angle_deg"].get<double>(),
            90.0);
  EXPECT_TRUE(result["warnings"].empty()) << result["warnings"];
  const nlohmann::json e = Evaluate(yoga, "y");
  EXPECT_EQ(e["e3d_frame"], "object");
  EXPECT_EQ(result["metrics"]["e3d_frame"], "object");
  EXPECT_EQ(result["metrics"]["e3d"].get<double>(), e["e3d"].get<double>());
  std::cout << "yoga e3D " << e["e3d"] << " (object frame), camera frame "
            << e["e3d_camera"] << ", rotation error " << e["rotation_error"]
            << "\n";
  // Measured 0.0238 / 0.0200 / 0.0096 (2026-11-27); bounds about 5 % above.
  EXPECT_LT(e["e3d"].get<double>(), 0.025);
  EXPECT_LT(e["e3d_camera"].get<double>(), 0.021);
  EXPECT_LT(e["rotation_error"].get<double>(), 0.0101);
}

// The other real sequences of the README's table at their published K,
// smaller K of yoga and pickup (docs/priors.md, K sweep), and frgc at K 5,
// with no other flag, scored as the field scores them: drink and pickup
// (truth S + Rs) in the object frame against the world S, face (truth
// P3_gt) and frgc (X) in the camera frame. Bounds about 5 % above what this
// test measured (in brackets), so that a change that costs accuracy fails
// here.
struct RealSequence {
  const char* name;
  int num_bases;
  const char* frame;
  double e3d;             // bound [measured]
  double e3d_camera;      // bound
  double rotation_error;  // bound; 0 when the truth has no rotations
  // LM iterations of every refinement stage together [measured]: a guard
  // of ±20 % (a change that doubles them fails here).
  int iterations;
};

class RealSequenceTest : public CliTest,
                         public ::testing::WithParamInterface<RealSequence> {};

TEST_P(RealSequenceTest, DefaultOptions) {
  NRSFM_SKIP_WITHOUT_SHARED_DATA(dir);
  if (testing_util::kSanitizedBuild)
    GTEST_SKIP() << "accuracy run: release build only";
  const RealSequence& c = GetParam();
  const std::string file = dir + "/" + c.name + ".mat";
  const RunResult r = Run("reconstruct --input " + file + " --K " +
                          std::to_string(c.num_bases) + " --output o --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const nlohmann::json e = Evaluate(file, "o");
  std::cout << c.name << " K = " << c.num_bases << ": e3D " << e["e3d"] << " ("
            << e["e3d_frame"] << " frame), camera frame " << e["e3d_camera"]
            << ", rotation error " << e.value("rotation_error", -1.0)
            << ", rank-K floor " << e.value("rank_floor", -1.0) << "\n";
  const nlohmann::json result =
      nlohmann::json::parse(ReadFile(Path("o/result.json")));
  int iterations = 0;
  for (const auto& stage : result["stages"])
    iterations += stage["iterations"].get<int>();
  EXPECT_GE(iterations, 0.8 * c.iterations) << iterations;
  EXPECT_LE(iterations, 1.2 * c.iterations) << iterations;
  EXPECT_EQ(e["e3d_frame"], c.frame);
  EXPECT_LT(e["e3d"].get<double>(), c.e3d);
  EXPECT_LT(e["e3d_camera"].get<double>(), c.e3d_camera);
  if (c.rotation_error > 0) {
    EXPECT_LT(e["rotation_error"].get<double>(), c.rotation_error);
    EXPECT_EQ(e["K"].get<int>(),
              c.num_bases);  // evaluate read it from result.json
    // Never below the rank-K floor: the floor and e3D are the same measure.
    EXPECT_GT(e["e3d"].get<double>(), e["rank_floor"].get<double>());
  }
}

INSTANTIATE_TEST_SUITE_P(
    Published, RealSequenceTest,
    ::testing::Values(
        RealSequence{"drink", 12, "object", 0.0134, 0.0111, 0.0062,
                     26},  // [.01272 .01059 .00576, 26]
        RealSequence{"pickup", 12, "object", 0.0263, 0.0254, 0.0050,
                     32},  // [.02486 .02394 .00469, 32]
        RealSequence{"face", 7, "camera", 0.0488, 0.0488, 0.0,
                     12},  // [.04785, 12]
        // K below the published one, where the data term alone stretched
        // the shapes (main 657e239: yoga K 4 18.5, K 6 5.49; pickup K 6 .492).
        RealSequence{"yoga", 4, "object", 0.0720, 0.0689, 0.0101,
                     34},  // [.06856 .06555 .00957, 21 + 13]
        RealSequence{"yoga", 6, "object", 0.0515, 0.0478, 0.0101,
                     63},  // [.04902 .04552 .00957, 21 + 42]
        RealSequence{"pickup", 6, "object", 0.0503, 0.0483, 0.0088,
                     52},  // [.04790 .04594 .00838, 22 + 30]
        // 400 different faces (not a video: the deformation prior, the
        // camera from K = 9 bases), truth X in the camera frame.
        RealSequence{"frgc", 5, "camera", 0.169, 0.169, 0.0,
                     43}),  // [.16096, 25 + 18]
    [](const ::testing::TestParamInfo<RealSequence>& info) {
      return std::string(info.param.name) + "_K" +
             std::to_string(info.param.num_bases);
    });

}  // namespace
}  // namespace nrsfm
