// The flags of tools/command_flags.h as a table: one row per flag of
// NRSFM_COMMAND_FLAGS (in its order), then one per extra term
// (problems/extra_terms.h). Everything that lists flags reads it: --help
// (RegisterCommandFlags), the options a command's flags set (ApplyFlags),
// result.json's "options" (OptionList), the keywords of the Python module and
// of the MATLAB function (by role), and SetFlagFromText. Nothing here prints
// or touches gflags; library target nrsfm_tools.
#ifndef NRSFM_TOOLS_FLAG_TABLE_H_
#define NRSFM_TOOLS_FLAG_TABLE_H_

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/model/status.h"
#include "problems/extra_terms.h"
#include "tools/command_flags.h"

namespace nrsfm {
namespace tools {

// "reconstruct", "evaluate", "synth" or "view".
const char* CommandName(Command command);

struct FlagInfo {
  std::string name;
  // the Python type of its value: "str", "int", "float", "bool"
  const char* type = "";
  FlagRole role = FlagRole::kTool;
  std::vector<CommandHelp> help;
  // The names the flag takes, "a|b|c", read from its parse function's error
  // on a name it does not know (core/model/enum_names.h, kExpectedOneOf): so
  // they are declared once, in the enum's name table. "" for a flag that
  // takes any value. HelpFor and full_help put them before each part.
  std::string choices;
  // The --help text: the parts of `help` with their commands named,
  // "reconstruct, view: …; synth: …".
  std::string full_help;
  // Whether the flag sets a field of FlagTargets (`apply` is empty if not).
  bool sets_option = false;

  // The value as result.json's "options" write it (numbers with 6 digits).
  std::function<std::string(const CommandFlags&)> text;
  // Sets the value from text as the command line gives it (by the type: an
  // integer, a number, true/false or 1/0, any string); errors name the flag
  // and the value.
  std::function<Status(const std::string&, CommandFlags*)> set_text;
  // Sets the flag's field of `targets` from the value; an error of a value
  // that does not parse (not yet named by the flag: ApplyFlags names it).
  std::function<Status(const CommandFlags&, FlagTargets*)> apply;

  bool Serves(Command command) const;
  // The help parts for `command` after "(choices) ", joined by " "; "" when
  // it does not serve it.
  std::string HelpFor(Command command) const;
};

// The range of an integer flag or keyword: ±kMaxFlagInteger.
inline constexpr long kMaxFlagInteger = 1000000000L;

// Every flag: NRSFM_COMMAND_FLAGS in order, then the extra terms' weights
// (role kOption, reconstruct only).
const std::vector<FlagInfo>& CommandFlagTable();

// The row of `name`; nullptr when there is none.
const FlagInfo* FindFlag(const std::string& name);

// The help of an extra term's weight flag (--smoothness, …): "weight of the
// <meaning>; <units>, 0 = off (docs/problem.md)."
std::string TermFlagHelp(const ExtraTerm& term);

// Sets every field of `targets` that a flag sets, from `flags`. Each value
// is judged by the library's Check() of its options struct with only that
// flag set, and its errors come under the flag's name (e.g. "--K_max: K
// selection: max_num_bases must be >= 2, got 1"); then the whole (
// FlagTargets::Check). A weight given to an extra term means priors =
// manual. `*targets` is reset first.
Status ApplyFlags(const CommandFlags& flags, FlagTargets* targets);

// Sets the flag `name` (a row of the table) from `text` (FlagInfo::set_text);
// an unknown name is an error ("unknown option 'x'").
Status SetFlagFromText(const std::string& name, const std::string& text,
                       CommandFlags* flags);

// The flags a reconstruction used, as result.json's "options": K (the K
// used) and K_flag (as given), then every flag of the roles kInput,
// kWeights, kStart and kOption in table order, as given (`cameras` 0 = from
// the file).
std::vector<std::pair<std::string, std::string>> OptionList(
    const CommandFlags& flags, int num_bases);

}  // namespace tools
}  // namespace nrsfm

#endif  // NRSFM_TOOLS_FLAG_TABLE_H_
