// Drives the real `nrsfm` binary: synth -> reconstruct -> evaluate round
// trips, every bad-input class, --help and --flagfile (the real sequences:
// tests/tools/cli_real_data_test.cc).

#include "tests/tools/cli_test.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "problems/extra_terms.h"
#include "tests/test_util.h"

namespace nrsfm {
namespace {

namespace fs = std::filesystem;

TEST_F(CliTest, HelpListsTheCommandsAndOnlyTheToolsFlags) {
  const RunResult r = Run("--help");
  EXPECT_EQ(r.exit_code, 0);
  const std::string text = r.out + r.err;
  EXPECT_NE(text.find("nrsfm reconstruct --input PATH"), std::string::npos)
      << text;
  EXPECT_NE(text.find("-robust_scale"), std::string::npos) << text;
  EXPECT_EQ(text.find("-logtostderr"), std::string::npos)
      << "glog flags leak into --help";
  // One flag per row of the extra-term table, described by the table.
  for (const ExtraTerm& term : ExtraTerms()) {
    EXPECT_NE(text.find(std::string("-") + term.name +
                        " (reconstruct: weight of the"),
              std::string::npos)
        << term.name;
  }
}

TEST_F(CliTest, MissingOrUnknownCommandIsAnError) {
  // A command line without a command is a usage error: exit code 2.
  ExpectFailure("",
                "nrsfm: expected exactly one command (reconstruct, evaluate, "
                "synth, view or track), "
                "got 0; see nrsfm --help",
                "", 2);
  ExpectFailure("reconstrut",
                "nrsfm: unknown command 'reconstrut' (expected reconstruct, "
                "evaluate, synth, view or track); see nrsfm --help",
                "", 2);
}

TEST_F(CliTest, RandomBasisRoundTrip) {
  ASSERT_EQ(Run("synth --dataset random --K 2 --frames 80 --points 25 --seed 3 "
                "--output r.mat")
                .exit_code,
            0);
  const RunResult r =
      Run("reconstruct --input r.mat --K 2 --output out --truth r.mat");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("e3D"), std::string::npos);
  EXPECT_NE(r.err.find("iteration"), std::string::npos) << "no progress lines";
  for (const char* file :
       {"points_camera.csv", "points_object.csv", "rotations.csv",
        "weights.csv", "basis.csv", "result.json"}) {
    EXPECT_TRUE(fs::exists(Path(std::string("out/") + file))) << file;
  }
  // Noise-free data with the generating K: the shapes are recovered.
  const nlohmann::json e = Evaluate("r.mat", "out");
  EXPECT_LT(e["e3d"].get<double>(), 1e-3);
  EXPECT_EQ(e["F"].get<int>(), 80);
  EXPECT_EQ(e["P"].get<int>(), 25);
  const nlohmann::json result =
      nlohmann::json::parse(ReadFile(Path("out/result.json")));
  EXPECT_TRUE(result.dump().find("e3d") != std::string::npos);
  // A result directory can also serve as the truth: comparing with itself is 0.
  EXPECT_LT(Evaluate("out", "out")["e3d"].get<double>(), 1e-12);
}

// synth --dataset reproject: a truth re-projected under a slow camera path is
// written like the Akhter et al. files (W, S, Rs) and scored in its object
// frame; noise-free exact-rank data are recovered in the camera frame.
TEST_F(CliTest, ReprojectRoundTripAndBadFlags) {
  ASSERT_EQ(Run("synth --dataset random --K 2 --frames 80 --points 25 --seed 3 "
                "--output r.mat")
                .exit_code,
            0);
  RunResult r =
      Run("synth --dataset reproject --input r.mat --rotation 120 "
          "--profile ramp --output rp.mat");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("rotation 120 deg (ramp)"), std::string::npos) << r.out;
  r = Run(
      "reconstruct --input rp.mat --K 2 --output out --truth rp.mat --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const nlohmann::json e = Evaluate("rp.mat", "out");
  EXPECT_EQ(e["e3d_frame"].get<std::string>(), "object");
  EXPECT_TRUE(e.contains("rotation_error"));
  EXPECT_LT(e["e3d_camera"].get<double>(), 1e-6);
  EXPECT_EQ(e["F"].get<int>(), 80);

  ExpectFailure("synth --dataset reproject --output x.mat",
                "--input is required", "x.mat");
  ExpectFailure(
      "synth --dataset reproject --input r.mat --profile jerky --output x.mat",
      "unknown value \"jerky\" (expected one of constant, ramp, stopgo)",
      "x.mat");
  ExpectFailure(
      "synth --dataset reproject --input r.mat --axis 1,2 --output x.mat",
      "--axis must be three numbers x,y,z, got '1,2'", "x.mat");
  ExpectFailure(
      "synth --dataset reproject --input r.mat --axis 0,0,0 --output x.mat",
      "axis must be a finite, non-zero direction", "x.mat");
  ExpectFailure(
      "synth --dataset reproject --input r.mat --noise 0.1 --output x.mat",
      "give --noise_fraction", "x.mat");
  ExpectFailure("synth --dataset reproject --input r.mat --K 3 --output x.mat",
                "do not apply to --dataset reproject", "x.mat");
  ExpectFailure(
      "synth --dataset reproject --input r.mat --rotation -5 --output x.mat",
      "total_rotation_deg", "x.mat");
  ExpectFailure("synth --dataset reproject --input nope.mat --output x.mat",
                "nope.mat: no such file", "x.mat");
}

TEST_F(CliTest, SuperquadricAndShoeRoundTrips) {
  ASSERT_EQ(
      Run("synth --dataset superquadric --frames 80 --points 60 --output q.mat")
          .exit_code,
      0);
  RunResult r =
      Run("reconstruct --input q.mat --K 4 --output q --truth q.mat --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  // Noise-free: measured 2.0e-10 % (release, 2026-11-27); the bound leaves
  // room for where the stopping rule (a relative cost change) ends.
  EXPECT_LT(Evaluate("q.mat", "q")["error3d_pct"].get<double>(), 1e-6);

  // Under the sanitizers the shoe has 60 points instead of 110 (half the
  // time; the same check).
  const int shoe_points = testing_util::kSanitizedBuild ? 60 : 110;
  ASSERT_EQ(Run("synth --dataset shoe --frames 100 --cameras 2 --points " +
                std::to_string(shoe_points) + " --output s.mat")
                .exit_code,
            0);
  r =
      Run("reconstruct --input s.mat --cameras 2 --K 4 --output s --truth "
          "s.mat --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  // points_camera.csv holds every frame, camera and point, missing ones too.
  const std::string csv = ReadFile(Path("s/points_camera.csv"));
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'),
            1 + 100 * 2 * shoe_points);
  // Noise-free: measured 2.1e-11 % (110 points) and 5.1e-11 % (60), release,
  // 2026-11-27.
  EXPECT_LT(Evaluate("s.mat", "s")["error3d_pct"].get<double>(), 1e-6);
}

// The camera count comes from the file when it records one (synth writes
// `cameras`): a one-camera shoe read with --cameras 2 is an error naming
// both counts, not 250 frames of two cameras; a two-camera file needs no flag.
TEST_F(CliTest, CamerasComeFromTheFile) {
  ASSERT_EQ(Run("synth --dataset shoe --frames 20 --output one.mat").exit_code,
            0);
  ExpectFailure("reconstruct --input one.mat --K 2 --cameras 2 --output o",
                "one.mat: the file records cameras = 1 (variable 'cameras') "
                "but 2 camera(s) "
                "were asked for",
                "o");
  ASSERT_EQ(Run("synth --dataset shoe --frames 20 --cameras 2 --output two.mat")
                .exit_code,
            0);
  const RunResult r =
      Run("reconstruct --input two.mat --K 2 --init factorization "
          "--max_iterations 3 "
          "--output t --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("F = 20, M = 2"), std::string::npos) << r.out;
  const nlohmann::json result =
      nlohmann::json::parse(ReadFile(Path("t/result.json")));
  EXPECT_EQ(result["num_cameras"], 2);
  EXPECT_EQ(result["options"]["cameras"], "0");  // as given: from the file
}

// Seeds 6 and 7 of the one-camera shoe have points seen in too few views
// for K = 4 (6 needed; on the 100 frames used here seed 6 points 40, 41, 85
// and seed 7 points 41, 42 are seen once; on the default 500 frames seed 7's
// point 41 is seen in 5 views, which the rule leaves out too, and the result
// is as exact; tests/solvers/pipeline/drop_unobserved_test.cc has that case):
// they are left out, named, NaN in the result, and the rest is exact; evaluate
// scores the rest and lists what it did not score.
TEST_F(CliTest, ShoeSeedsWithPointsSeenTooRarelyReconstruct) {
  std::vector<std::vector<int>> dropped = {{40, 41, 85}, {41, 42}};
  std::vector<int> seeds = {6, 7};
  int frames = 100;
  if (testing_util::kSanitizedBuild) {
    // Under the sanitizers seed 6 on 30 frames alone (the same code path;
    // fewer views leave point 42 seen once too).
    dropped = {{40, 41, 42, 85}};
    seeds = {6};
    frames = 30;
  }
  for (int seed : seeds) {
    SCOPED_TRACE(seed);
    const std::string name = "shoe" + std::to_string(seed);
    ASSERT_EQ(
        Run("synth --dataset shoe --frames " + std::to_string(frames) +
            " --seed " + std::to_string(seed) + " --output " + name + ".mat")
            .exit_code,
        0);
    const RunResult r =
        Run("reconstruct --input " + name + ".mat --K 4 --output " + name +
            " --truth " + name + ".mat --quiet");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("warning: left out of the reconstruction"),
              std::string::npos)
        << r.out;
    const nlohmann::json result =
        nlohmann::json::parse(ReadFile(Path(name + "/result.json")));
    EXPECT_EQ(result["dropped_points"].get<std::vector<int>>(),
              dropped[seed - 6]);
    EXPECT_TRUE(result["dropped_frames"].empty());
    EXPECT_LT(result["metrics"]["e3d"].get<double>(), 1e-6);
    const nlohmann::json e = Evaluate(name + ".mat", name);
    EXPECT_LT(e["error3d_pct"].get<double>(), 1e-4);
    EXPECT_EQ(e["unscored_points"].get<std::vector<int>>(), dropped[seed - 6]);
    EXPECT_EQ(e["P"].get<int>(), 110);
  }
}

TEST_F(CliTest, ExtraTermFlags) {
  ASSERT_EQ(Run("synth --dataset shoe --frames 40 --cameras 2 --output s.mat")
                .exit_code,
            0);
  ASSERT_EQ(Run("synth --dataset shoe --frames 40 --output s1.mat").exit_code,
            0);
  ExpectFailure("reconstruct --input s1.mat --K 2 --rigidity 10 --output o",
                "s1.mat: --rigidity: needs data from M >= 2 synchronised "
                "cameras, got M = 1",
                "o");
  ExpectFailure(
      "reconstruct --input s1.mat --K 2 --cameras 1 --rigidity 10 --output o",
      "s1.mat: --rigidity: needs data from M >= 2 synchronised cameras, got M "
      "= 1",
      "o");
  ExpectFailure(
      "reconstruct --input s.mat --cameras 2 --K 2 --temporal -1 --output o",
      "--temporal: problem options: term weight temporal must be finite and >= "
      "0, "
      "got -1",
      "o");
  ExpectFailure(
      "reconstruct --input s.mat --K 2 --temporal_shape -1 --output o",
      "term weight temporal_shape must be finite and >= 0, got -1", "o");
  ExpectFailure(
      "reconstruct --input s.mat --K 2 --rotation_acceleration nan --output o",
      "term weight rotation_acceleration must be finite and >= 0, got nan",
      "o");
  // The reconstruction with the terms: ~6 s in the release build (336 LM
  // iterations: the temporal-weights term is not invariant to the scale
  // gauge, docs/problem.md), so not under the sanitizers; the terms' code
  // runs there in tests/solvers/start/extra_terms_test.
  if (testing_util::kSanitizedBuild) return;
  const RunResult r =
      Run("reconstruct --input s.mat --cameras 2 --K 2 --rigidity 100 "
          "--smoothness 0.01 --temporal 1 --output s --truth s.mat --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const nlohmann::json result =
      nlohmann::json::parse(ReadFile(Path("s/result.json")));
  // Every term's weight is in result.json under its flag.
  for (const ExtraTerm& term : ExtraTerms()) {
    EXPECT_TRUE(result["options"].contains(term.name)) << term.name;
  }
  EXPECT_EQ(result["options"]["rigidity"], "100");
  EXPECT_EQ(result["options"]["temporal"], "1");
  // Measured 3.0135 % with the terms (K = 2 for a shoe of K = 4, 40
  // frames; the command above, then `nrsfm evaluate --truth s.mat --result
  // s`); the bound about 13 % above. The same run without them ends at
  // 57.7 %.
  EXPECT_LT(Evaluate("s.mat", "s")["error3d_pct"].get<double>(), 3.4);
}

// A term weight on the command line means manual priors: exactly that term.
TEST_F(CliTest, TermFlagMeansManualPriors) {
  ASSERT_EQ(
      Run("synth --dataset random --K 1 --frames 30 --points 12 --output r.mat")
          .exit_code,
      0);
  const RunResult r =
      Run("reconstruct --input r.mat --K 1 --temporal 0.5 --output m --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json result =
      nlohmann::json::parse(ReadFile(Path("m/result.json")));
  EXPECT_EQ(result["term_weights"].size(), 1u);
  EXPECT_EQ(result["term_weights"]["temporal"].get<double>(), 0.5);
  ExpectFailure("reconstruct --input r.mat --K 1 --priors sometimes --output o",
                "--priors: prior mode: unknown value \"sometimes\" (expected "
                "one of auto, manual)",
                "o");
}

TEST_F(CliTest, FlagfileWorks) {
  ASSERT_EQ(
      Run("synth --dataset random --K 1 --frames 30 --points 12 --output r.mat")
          .exit_code,
      0);
  std::ofstream(Path("flags.txt"))
      << "--input=r.mat\n--K=1\n--output=ff\n--quiet\n";
  const RunResult r = Run("reconstruct --flagfile=flags.txt");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(Path("ff/result.json")));
}

TEST_F(CliTest, BadInputGetsOneClearLineAndNoOutput) {
  ASSERT_EQ(
      Run("synth --dataset random --K 1 --frames 20 --points 10 --output r.mat")
          .exit_code,
      0);
  ExpectFailure("reconstruct --input nope.mat --K 1 --output o",
                "error: nope.mat: no such file", "o");
  ExpectFailure("reconstruct --input r.mat --var Q --K 1 --output o",
                "r.mat: no variable 'Q'; the file has: W, P3_gt,", "o");
  ExpectFailure("reconstruct --input r.mat --K 0 --output o",
                "--K: must be an integer >= 1 or 'auto', got '0'", "o");
  ExpectFailure("reconstruct --input r.mat --K many --output o",
                "--K: must be an integer >= 1 or 'auto', got 'many'", "o");
  ExpectFailure("reconstruct --input r.mat --K 9 --output o",  // 3K+1 > P
                "r.mat: start: K = 9 needs 3K + 1 = 28 points and 2F >= "
                "28; got P = 10, "
                "F = 20",
                "o");
  ExpectFailure("reconstruct --input r.mat --K 1 --init best --output o",
                "--init: start: unknown value \"best\" (expected one of auto, "
                "factorization, "
                "rigid, triple)",
                "o");
  ExpectFailure("reconstruct --input r.mat --K 1 --robust tukey --output o",
                "--robust: robust loss: unknown value \"tukey\" (expected one "
                "of none, huber, "
                "cauchy)",
                "o");
  // --quiet: the progress lines of the solve before the write go to stderr.
  ExpectFailure(
      "reconstruct --input r.mat --K 1 --output /proc/nrsfm_out --quiet",
      "/proc: cannot create a directory there");
  ExpectFailure("reconstruct --input r.mat --K 1",
                "error: --output is required");
  ExpectFailure(
      "reconstruct --input r.mat --K 1 --max_iterations -3 --output o",
      "max_iterations must be >= 0, got -3", "o");

  // Text inputs: Inf, odd rows, a bad token.
  std::ofstream(Path("inf.txt")) << "1 2 3\n4 inf 6\n";
  ExpectFailure("reconstruct --input inf.txt --K 1 --output o",
                "inf.txt: line 2, column 2: infinite value 'inf'; use NaN to "
                "mark a missing "
                "value",
                "o");
  std::ofstream(Path("odd.txt")) << "1 2 3\n4 5 6\n7 8 9\n";
  ExpectFailure(
      "reconstruct --input odd.txt --K 1 --output o",
      "odd.txt: 3 rows is not a multiple of 2 (expected rows u, v per frame)",
      "o");
  std::ofstream(Path("token.txt")) << "1 2 x3\n4 5 6\n";
  ExpectFailure("reconstruct --input token.txt --K 1 --output o",
                "token.txt: line 1, column 3: 'x3' is not a number", "o");
  // A truncated .mat file.
  const std::string mat = ReadFile(Path("r.mat"));
  std::ofstream(Path("cut.mat"), std::ios::binary)
      << mat.substr(0, mat.size() / 2);
  ExpectFailure("reconstruct --input cut.mat --K 1 --output o",
                "cut.mat: the .mat file is truncated or corrupt (", "o");

  // A non-empty output directory is not replaced without --overwrite.
  fs::create_directory(Path("full"));
  std::ofstream(Path("full/keep.txt")) << "x";
  ExpectFailure("reconstruct --input r.mat --K 1 --output full",
                "output 'full' exists and is not an empty directory (use "
                "--overwrite to replace "
                "an earlier result)");
  EXPECT_TRUE(fs::exists(Path("full/keep.txt")));

  // evaluate and synth.
  ExpectFailure("evaluate --truth r.mat --result missing_dir",
                "nrsfm evaluate: error: missing_dir: no such file");
  ExpectFailure("evaluate --truth nope.mat --result o",
                "nrsfm evaluate: error: nope.mat: no such file");
  ExpectFailure("synth --dataset cube --output c.mat",
                "--dataset: unknown value \"cube\" (expected one of random, "
                "superquadric, shoe, reproject)");
  ExpectFailure("synth --dataset random --frames 1 --output c.mat",
                "num_frames must be >= 2, got 1");
  ExpectFailure("synth --dataset random --output c.txt",
                "--output must name a .mat file, got 'c.txt'");
}

// Under the sanitizers the same check runs on 60 x 30 points with K <= 6
// (about 5x less work than 100 x 40 with K <= 7).
TEST_F(CliTest, AutoKFindsTheGeneratingK) {
  // 20 s in the release build, 140 s under the sanitizers, which run the
  // same selection in tests/solvers/select_num_bases_test.
  if (testing_util::kSanitizedBuild) GTEST_SKIP() << "release build only";
  const std::string size = testing_util::kSanitizedBuild
                               ? " --frames 60 --points 30"
                               : " --frames 100 --points 40";
  const std::string k_max = testing_util::kSanitizedBuild ? "6" : "7";
  for (int k : {2, 3, 5}) {
    const std::string mat = "k" + std::to_string(k) + ".mat";
    ASSERT_EQ(Run("synth --dataset random --K " + std::to_string(k) + size +
                  " --noise 0.005 --seed 7 --output " + mat)
                  .exit_code,
              0);
    const RunResult r =
        Run("reconstruct --input " + mat + " --K auto --K_max " + k_max +
            " --output a" + std::to_string(k) + " --quiet");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("K = " + std::to_string(k) + ","), std::string::npos)
        << "generated with K = " << k << ":\n"
        << r.out;
  }
}

}  // namespace
}  // namespace nrsfm
