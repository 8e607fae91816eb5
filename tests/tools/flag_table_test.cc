// The table of the tool's flags (tools/flag_table.h).
#include "tools/flag_table.h"

#include <gtest/gtest.h>

#include <map>

namespace nrsfm {
namespace tools {
namespace {

TEST(CommandFlagTable, OneRowPerFlagAndTermWithItsCommands) {
  const std::vector<FlagInfo>& table = CommandFlagTable();
  std::size_t flags = 0;
#define NRSFM_COUNT_FLAG(type, flag, value, role, bind, help) \
  EXPECT_EQ(table.at(flags++).name, #flag);
  NRSFM_COMMAND_FLAGS(NRSFM_COUNT_FLAG)
#undef NRSFM_COUNT_FLAG
  ASSERT_EQ(table.size(), flags + ExtraTerms().size());
  for (std::size_t i = 0; i < ExtraTerms().size(); ++i) {
    EXPECT_EQ(table[flags + i].name, ExtraTerms()[i].name);
    EXPECT_EQ(table[flags + i].role, FlagRole::kOption);
  }
  std::map<std::string, int> seen;
  for (const FlagInfo& flag : table) {
    EXPECT_EQ(++seen[flag.name], 1) << flag.name;
    EXPECT_TRUE(flag.Serves(kReconstruct) || flag.Serves(kEvaluate) ||
                flag.Serves(kSynth) || flag.Serves(kView) ||
                flag.Serves(kTrack))
        << flag.name;
    // A flag that sets an option serves reconstruct, view or track
    // (ApplyFlags).
    if (flag.sets_option) {
      EXPECT_TRUE(flag.Serves(kReconstruct) || flag.Serves(kView) ||
                  flag.Serves(kTrack))
          << flag.name;
    }
  }
  // The help of one command, and the --help text with the commands named.
  const FlagInfo* cameras = FindFlag("cameras");
  ASSERT_NE(cameras, nullptr);
  EXPECT_EQ(cameras->HelpFor(kSynth), "cameras of the shoe (1 or 2; 0 = 1).");
  EXPECT_EQ(cameras->HelpFor(kEvaluate), "");
  EXPECT_EQ(cameras->full_help.rfind(
                "reconstruct: number of synchronised cameras", 0),
            0u);
  EXPECT_NE(cameras->full_help.find(" synth: cameras of the shoe"),
            std::string::npos);
  EXPECT_EQ(FindFlag("var")->full_help.rfind("reconstruct, view: variable", 0),
            0u);
  EXPECT_EQ(FindFlag("bogus"), nullptr);
}

// The names a flag takes come from the enum's name table (its parse
// function's error), never typed into its help.
TEST(FlagTable, ChoicesComeFromTheNameTables) {
  EXPECT_EQ(FindFlag("camera")->choices, "weak_perspective|perspective");
  EXPECT_EQ(FindFlag("robust")->choices, "none|huber|cauchy");
  EXPECT_EQ(FindFlag("hold")->choices,
            "rotations|translations|weights|basis|scales|rig");
  EXPECT_EQ(FindFlag("dataset")->choices, "random|superquadric|shoe|reproject");
  EXPECT_EQ(FindFlag("profile")->choices, "constant|ramp|stopgo");
  EXPECT_EQ(FindFlag("track_method")->choices, "rank|lk");
  EXPECT_EQ(FindFlag("K")->choices, "");
  EXPECT_EQ(FindFlag("output")->choices, "");
  EXPECT_EQ(FindFlag("robust")->HelpFor(kReconstruct),
            "(none|huber|cauchy) robust loss on the reprojection terms.");
  int with_choices = 0;
  for (const FlagInfo& flag : CommandFlagTable()) {
    if (flag.choices.empty()) continue;
    ++with_choices;
    const std::string first = flag.choices.substr(0, flag.choices.find('|'));
    for (const CommandHelp& part : flag.help) {
      EXPECT_EQ(std::string(part.text).find(first + "|"), std::string::npos)
          << flag.name << ": " << part.text;
    }
  }
  // format, part, init, camera, priors, robust, hold, minimizer,
  // linear_solver, dataset, profile, track_method.
  EXPECT_EQ(with_choices, 12);
}

TEST(ApplyFlags, SetsTheOptionFieldOfEachFlag) {
  CommandFlags flags;
  FlagTargets targets;
  ASSERT_TRUE(ApplyFlags(flags, &targets).ok());
  EXPECT_EQ(targets.reconstruct.priors, PriorMode::kAuto);
  EXPECT_FALSE(targets.num_bases.given);
  flags.var = "W2";
  flags.format = "text";
  flags.min_confidence = 0.5;
  flags.cameras = 2;
  flags.K = "auto";
  flags.K_max = 5;
  flags.init = "rigid";
  flags.hold = "basis,rotations";
  flags.max_iterations = 7;
  flags.function_tolerance = 1e-9;
  flags.max_seconds = 30.0;
  flags.seed = 11;
  flags.smoothness_reference_frame = 4;
  flags.cg_tolerance = 0.05;
  flags.completion_iterations = 9;
  flags.alternation_rounds = 3;
  flags.rule_min_track_order = 2.0;
  flags.term_weights[0] = 2.5;
  ASSERT_TRUE(ApplyFlags(flags, &targets).ok())
      << ApplyFlags(flags, &targets).message();
  EXPECT_EQ(targets.input.variable, "W2");
  EXPECT_EQ(targets.input.format, InputFormat::kText);
  EXPECT_EQ(targets.input.keypoints.min_confidence, 0.5);
  EXPECT_EQ(targets.input.num_cameras, 2);
  EXPECT_TRUE(targets.num_bases.given && targets.num_bases.automatic);
  EXPECT_EQ(targets.select.max_num_bases, 5);
  EXPECT_EQ(targets.reconstruct.start.method, StartMethod::kRigid);
  EXPECT_TRUE(targets.reconstruct.problem.constant_basis);
  EXPECT_TRUE(targets.reconstruct.problem.constant_rotations);
  EXPECT_FALSE(targets.reconstruct.problem.constant_weights);
  EXPECT_EQ(targets.reconstruct.solver.max_iterations, 7);
  EXPECT_EQ(targets.reconstruct.solver.function_tolerance, 1e-9);
  EXPECT_EQ(targets.reconstruct.solver.max_seconds, 30.0);
  EXPECT_EQ(targets.reconstruct.start.seed, 11u);
  EXPECT_EQ(targets.reconstruct.problem.smoothness_edges.reference_frame, 4);
  EXPECT_EQ(targets.reconstruct.solver.cg_relative_tolerance, 0.05);
  EXPECT_EQ(targets.reconstruct.start.completion.max_iterations, 9);
  EXPECT_EQ(targets.reconstruct.start.alternation.rounds, 3);
  EXPECT_EQ(targets.reconstruct.prior_rule.min_track_order, 2.0);
  EXPECT_EQ(targets.reconstruct.problem.TermWeight(ExtraTerms()[0].name), 2.5);
  // A weight given is a manual choice of the terms.
  EXPECT_EQ(targets.reconstruct.priors, PriorMode::kManual);
  flags.K = "7";
  ASSERT_TRUE(ApplyFlags(flags, &targets).ok());
  EXPECT_TRUE(targets.num_bases.given && !targets.num_bases.automatic);
  EXPECT_EQ(targets.num_bases.value, 7);
}

TEST(ApplyFlags, NamesTheFlagAndTheValue) {
  CommandFlags flags;
  FlagTargets targets;
  flags.init = "best";
  EXPECT_EQ(ApplyFlags(flags, &targets).message().rfind("--init: ", 0), 0u)
      << ApplyFlags(flags, &targets).message();
  flags = CommandFlags();
  flags.term_weights[0] = -1.0;
  // The rule is ProblemOptions::Check()'s; the message names the flag.
  EXPECT_EQ(ApplyFlags(flags, &targets).message(),
            std::string("--") + ExtraTerms()[0].name +
                ": problem options: term weight " + ExtraTerms()[0].name +
                " must be finite and >= 0, got -1");
  flags = CommandFlags();
  flags.K = "auto";
  flags.K_max = 1;
  EXPECT_EQ(ApplyFlags(flags, &targets).message(),
            "--K_max: K selection: max_num_bases must be >= 2, got 1");
  flags = CommandFlags();
  flags.K = "0";
  EXPECT_EQ(ApplyFlags(flags, &targets).message(),
            "--K: must be an integer >= 1 or 'auto', got '0'");
  flags = CommandFlags();
  flags.hold = "basis,cameras";
  EXPECT_EQ(ApplyFlags(flags, &targets).message(),
            "--hold: kind of block: unknown value \"cameras\" (expected one "
            "of rotations, translations, weights, basis, scales, rig)");
  flags = CommandFlags();
  flags.cameras = -1;
  EXPECT_EQ(ApplyFlags(flags, &targets).message().rfind("--cameras: ", 0), 0u)
      << ApplyFlags(flags, &targets).message();
  flags = CommandFlags();
  flags.cg_tolerance = 1.5;
  EXPECT_EQ(ApplyFlags(flags, &targets).message(),
            "--cg_tolerance: solver options: cg_relative_tolerance must be in "
            "(0, 1), got "
            "1.500000");
  flags = CommandFlags();
  flags.threads = 0;
  EXPECT_EQ(ApplyFlags(flags, &targets).message().rfind("--threads: ", 0), 0u)
      << ApplyFlags(flags, &targets).message();
  NumBasesFlag k;
  ASSERT_TRUE(ParseNumBasesFlag("auto", &k).ok());
  EXPECT_TRUE(k.given && k.automatic);
  ASSERT_TRUE(ParseNumBasesFlag("", &k).ok());
  EXPECT_FALSE(k.given);
}

// result.json's "options" come from the one flag list and the term table:
// every reconstruct flag but the tool's own files, once.
// The MATLAB function sets flags by name from text, as the command line
// gives them.
TEST(SetFlagFromText, ParsesByTheFlagsType) {
  CommandFlags flags;
  ASSERT_TRUE(SetFlagFromText("max_iterations", "7", &flags).ok());
  EXPECT_EQ(flags.max_iterations, 7);
  ASSERT_TRUE(SetFlagFromText("robust_scale", "0.25", &flags).ok());
  EXPECT_EQ(flags.robust_scale, 0.25);
  ASSERT_TRUE(SetFlagFromText("init", "rigid", &flags).ok());
  EXPECT_EQ(flags.init, "rigid");
  ASSERT_TRUE(SetFlagFromText("ply", "true", &flags).ok());
  EXPECT_TRUE(flags.ply);
  ASSERT_TRUE(SetFlagFromText("ply", "0", &flags).ok());
  EXPECT_FALSE(flags.ply);
  ASSERT_TRUE(SetFlagFromText("seed", "18446744073709551615", &flags).ok());
  EXPECT_EQ(flags.seed, 18446744073709551615ULL);
  ASSERT_TRUE(SetFlagFromText(ExtraTerms()[0].name, "1e3", &flags).ok());
  EXPECT_EQ(flags.term_weights[0], 1000.0);

  EXPECT_EQ(SetFlagFromText("max_iterations", "7.5", &flags).message(),
            "max_iterations must be an integer, got '7.5'");
  EXPECT_EQ(SetFlagFromText("robust_scale", "big", &flags).message(),
            "robust_scale must be a number, got 'big'");
  EXPECT_EQ(SetFlagFromText("robust_scale", "2x", &flags).message(),
            "robust_scale must be a number, got '2x'");
  EXPECT_EQ(SetFlagFromText("ply", "yes", &flags).message(),
            "ply must be true or false, got 'yes'");
  EXPECT_EQ(SetFlagFromText("seed", "-1", &flags).message(),
            "seed must be an integer in [0, 2^64), got '-1'");
  EXPECT_EQ(SetFlagFromText("bogus", "1", &flags).message(),
            "unknown option 'bogus'");
  EXPECT_EQ(flags.max_iterations, 7);  // a failed parse leaves the flag
  EXPECT_EQ(flags.robust_scale, 0.25);
}

TEST(OptionList, EveryReconstructFlagOnce) {
  CommandFlags flags;
  flags.K = "auto";
  const std::vector<std::pair<std::string, std::string>> list =
      OptionList(flags, 3);
  std::map<std::string, std::string> options;
  for (const auto& [name, value] : list)
    EXPECT_TRUE(options.emplace(name, value).second) << name;
  EXPECT_EQ(options["K"], "3");
  EXPECT_EQ(options["K_flag"], "auto");
  // Every flag of the roles of a reconstruction's options, none of the
  // tool's own files or the synthetic data.
  for (const FlagInfo& flag : CommandFlagTable()) {
    const bool option =
        flag.role == FlagRole::kInput || flag.role == FlagRole::kWeights ||
        flag.role == FlagRole::kStart || flag.role == FlagRole::kOption;
    EXPECT_EQ(options.count(flag.name) > 0, option || flag.name == "K")
        << flag.name;
  }
  EXPECT_EQ(options.count("output"), 0u);
  EXPECT_EQ(options.count("dataset"), 0u);
  EXPECT_EQ(options["var"], "");
  for (const ExtraTerm& term : ExtraTerms())
    EXPECT_EQ(options[term.name], "0") << term.name;
  EXPECT_EQ(options["K_threshold"], "1.1");
  EXPECT_EQ(options["seed"], "1");
}

}  // namespace
}  // namespace tools
}  // namespace nrsfm
