// The steps the nrsfm tool and the Python module share (tools/flag_options.h).
#include "tools/flag_options.h"

#include <map>

#include <gtest/gtest.h>

namespace nrsfm {
namespace tools {
namespace {

TEST(FlagHelpFor, TakesThePartOfOneCommand) {
  EXPECT_EQ(FlagHelpFor("reconstruct, view: input file (.mat).", "view"), "input file (.mat).");
  EXPECT_EQ(FlagHelpFor("reconstruct, view: input file (.mat).", "synth"), "");
  EXPECT_EQ(FlagHelpFor("reconstruct: number of bases; synth: bases of the random generator.",
                        "synth"),
            "bases of the random generator.");
  EXPECT_EQ(FlagHelpFor("reconstruct: M; 0 = the file. synth: shoe (1 or 2; 0 = 1).",
                        "reconstruct"),
            "M; 0 = the file.");
  EXPECT_EQ(FlagHelpFor("reconstruct --K auto: largest K tried.", "reconstruct"),
            "(--K auto) largest K tried.");
  // Every flag serves some command.
#define NRSFM_CHECK_FLAG_HELP(type, name, value, help)                            \
  EXPECT_FALSE(FlagHelpFor(help, "reconstruct").empty() &&                       \
               FlagHelpFor(help, "evaluate").empty() &&                          \
               FlagHelpFor(help, "synth").empty() && FlagHelpFor(help, "view").empty()) \
      << #name;
  NRSFM_COMMAND_FLAGS(NRSFM_CHECK_FLAG_HELP)
#undef NRSFM_CHECK_FLAG_HELP
}

TEST(BuildReconstructOptions, NamesTheFlagAndTheValue) {
  CommandFlags flags;
  ReconstructOptions options;
  ASSERT_TRUE(BuildReconstructOptions(flags, &options).ok());
  EXPECT_EQ(options.priors, PriorMode::kAuto);
  flags.init = "best";
  EXPECT_EQ(BuildReconstructOptions(flags, &options).message().rfind("--init: ", 0), 0u)
      << BuildReconstructOptions(flags, &options).message();
  flags = CommandFlags();
  flags.term_weights[0] = -1.0;
  // The rule is ProblemOptions::Check()'s; the message names the flag.
  EXPECT_EQ(BuildReconstructOptions(flags, &options).message(),
            std::string("--") + ExtraTerms()[0].name + ": problem options: term weight " +
                ExtraTerms()[0].name + " must be finite and >= 0, got -1");
  flags = CommandFlags();
  flags.K = "auto";
  flags.K_max = 1;
  EXPECT_EQ(BuildReconstructOptions(flags, &options).message(),
            "--K_max: K selection: max_num_bases must be >= 2, got 1");
  bool auto_k = false;
  int k = 0;
  EXPECT_EQ(ParseNumBasesFlag("0", &auto_k, &k).message(),
            "--K must be an integer >= 1 or 'auto', got '0'");
  ASSERT_TRUE(ParseNumBasesFlag("auto", &auto_k, &k).ok());
  EXPECT_TRUE(auto_k);
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
  EXPECT_EQ(SetFlagFromText("bogus", "1", &flags).message(), "unknown option 'bogus'");
  EXPECT_EQ(flags.max_iterations, 7);  // a failed parse leaves the flag
  EXPECT_EQ(flags.robust_scale, 0.25);
}

TEST(OptionList, EveryReconstructFlagOnce) {
  CommandFlags flags;
  flags.K = "auto";
  const std::vector<std::pair<std::string, std::string>> list = OptionList(flags, 3);
  std::map<std::string, std::string> options;
  for (const auto& [name, value] : list) EXPECT_TRUE(options.emplace(name, value).second) << name;
  EXPECT_EQ(options["K"], "3");
  EXPECT_EQ(options["K_flag"], "auto");
#define NRSFM_CHECK_OPTION(type, name, value, help)                                 \
  EXPECT_EQ(options.count(#name) > 0, !FlagHelpFor(help, "reconstruct").empty() && \
                                           ToolOnlyFlags().count(#name) == 0)       \
      << #name;
  NRSFM_COMMAND_FLAGS(NRSFM_CHECK_OPTION)
#undef NRSFM_CHECK_OPTION
  for (const ExtraTerm& term : ExtraTerms()) EXPECT_EQ(options[term.name], "0") << term.name;
  EXPECT_EQ(options["K_threshold"], "1.1");
  EXPECT_EQ(options["seed"], "1");
}

}  // namespace
}  // namespace tools
}  // namespace nrsfm
