#include "tools/flag_table.h"

#include <cstdint>
#include <iomanip>
#include <sstream>
#include <type_traits>

#include "core/model/enum_names.h"
#include "core/synthetic/synthetic.h"
#include "tools/synth_steps.h"

namespace nrsfm {
namespace tools {
namespace {

constexpr Command kCommands[] = {kReconstruct, kEvaluate, kSynth, kView,
                                 kTrack};

std::string FormatDouble(double value) {
  std::ostringstream s;
  s << std::setprecision(6) << value;
  return s.str();
}

// A flag's value as result.json's "options" write it.
std::string FlagText(const std::string& value) { return value; }
std::string FlagText(int value) { return std::to_string(value); }
std::string FlagText(std::uint64_t value) { return std::to_string(value); }
std::string FlagText(double value) { return FormatDouble(value); }
std::string FlagText(bool value) { return value ? "true" : "false"; }

// The Python name of a flag's type.
template <typename T>
const char* TypeName() {
  if constexpr (std::is_same_v<T, std::string>) return "str";
  if constexpr (std::is_same_v<T, bool>) return "bool";
  if constexpr (std::is_floating_point_v<T>) return "float";
  return "int";
}

// Parses a whole string as an integer in ±kMaxFlagInteger; false on
// anything else.
bool ParseInt(const std::string& s, int* value) {
  if (s.empty()) return false;
  size_t used = 0;
  try {
    const long v = std::stol(s, &used);
    if (used != s.size() || v < -kMaxFlagInteger || v > kMaxFlagInteger) {
      return false;
    }
    *value = static_cast<int>(v);
  } catch (...) {
    return false;
  }
  return true;
}

Status ParseFlagText(const std::string& /*name*/, const std::string& text,
                     std::string* value) {
  *value = text;
  return Status::OK();
}

Status ParseFlagText(const std::string& name, const std::string& text,
                     int* value) {
  if (ParseInt(text, value)) return Status::OK();
  return Status::Error(name + " must be an integer, got '" + text + "'");
}

Status ParseFlagText(const std::string& name, const std::string& text,
                     std::uint64_t* value) {
  try {
    std::size_t used = 0;
    const unsigned long long v = std::stoull(text, &used);
    if (used == text.size() && text.find('-') == std::string::npos) {
      *value = static_cast<std::uint64_t>(v);
      return Status::OK();
    }
  } catch (...) {
  }
  return Status::Error(name + " must be an integer in [0, 2^64), got '" + text +
                       "'");
}

Status ParseFlagText(const std::string& name, const std::string& text,
                     double* value) {
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size()) {
      *value = v;
      return Status::OK();
    }
  } catch (...) {
  }
  return Status::Error(name + " must be a number, got '" + text + "'");
}

Status ParseFlagText(const std::string& name, const std::string& text,
                     bool* value) {
  if (text == "true" || text == "1") {
    *value = true;
  } else if (text == "false" || text == "0") {
    *value = false;
  } else {
    return Status::Error(name + " must be true or false, got '" + text + "'");
  }
  return Status::OK();
}

// "(a|b|c) " before a help part of a flag with choices, "" otherwise.
std::string ChoicesPrefix(const std::string& choices) {
  return choices.empty() ? "" : "(" + choices + ") ";
}

std::string FullHelp(const std::vector<CommandHelp>& help,
                     const std::string& choices) {
  std::string out;
  for (const CommandHelp& part : help) {
    std::string heads;
    for (Command command : kCommands) {
      if ((part.commands & command) == 0) continue;
      heads += (heads.empty() ? "" : ", ") + std::string(CommandName(command));
    }
    out += (out.empty() ? "" : " ") + heads + ": " + ChoicesPrefix(choices) +
           part.text;
  }
  return out;
}

// A name no parse function accepts: what a flag's choices are read with.
constexpr char kNoName[] = "\x01";

// The names listed by an error of ParseName (or one worded like it), joined
// by '|'; "" for any other status.
std::string ChoicesIn(const Status& error) {
  const std::string& message = error.message();
  const std::size_t list = message.find(kExpectedOneOf);
  if (error.ok() || list == std::string::npos) return "";
  const std::size_t begin = list + sizeof(kExpectedOneOf) - 1;
  const std::size_t end = message.find(')', begin);
  std::string choices;
  for (std::size_t at = begin; at < end && at < message.size(); ++at) {
    if (message.compare(at, 2, ", ") == 0) {
      choices += '|';
      ++at;
    } else {
      choices += message[at];
    }
  }
  return choices;
}

// A row of NRSFM_COMMAND_FLAGS: its member of CommandFlags and its bind.
template <typename T, typename Bind>
FlagInfo MakeFlagInfo(const char* name, FlagRole role,
                      std::vector<CommandHelp> help, T CommandFlags::*member,
                      Bind bind) {
  FlagInfo info;
  info.name = name;
  info.type = TypeName<T>();
  info.role = role;
  info.help = std::move(help);
  if constexpr (std::is_same_v<T, std::string> &&
                !std::is_same_v<Bind, SetsNothing>) {
    FlagTargets scratch;
    info.choices = ChoicesIn(bind(std::string(kNoName), &scratch));
  }
  info.full_help = FullHelp(info.help, info.choices);
  info.text = [member](const CommandFlags& flags) {
    return FlagText(flags.*member);
  };
  info.set_text = [member, flag = info.name](const std::string& text,
                                             CommandFlags* flags) {
    return ParseFlagText(flag, text, &(flags->*member));
  };
  if constexpr (!std::is_same_v<Bind, SetsNothing>) {
    info.sets_option = true;
    info.apply = [member, bind](const CommandFlags& flags,
                                FlagTargets* targets) {
      return bind(flags.*member, targets);
    };
  }
  return info;
}

std::vector<FlagInfo> MakeTable() {
  std::vector<FlagInfo> table;
#define NRSFM_FLAG_ROW(type, name, value, role, bind, help)       \
  table.push_back(MakeFlagInfo<type>(#name, FlagRole::role, help, \
                                     &CommandFlags::name, bind));
  NRSFM_COMMAND_FLAGS(NRSFM_FLAG_ROW)
#undef NRSFM_FLAG_ROW
  // The flags with choices that the commands read themselves.
  SpeedProfile profile;
  const std::pair<const char*, Status> read_by_commands[] = {
      {"dataset", CheckSynthDataset(kNoName)},
      {"profile", ParseSpeedProfile(kNoName, &profile)}};
  for (FlagInfo& info : table) {
    for (const auto& [name, error] : read_by_commands) {
      if (info.name != name) continue;
      info.choices = ChoicesIn(error);
      info.full_help = FullHelp(info.help, info.choices);
    }
  }
  static const std::vector<std::string> term_help = [] {
    std::vector<std::string> help;
    for (const ExtraTerm& term : ExtraTerms())
      help.push_back(TermFlagHelp(term));
    return help;
  }();
  const std::vector<ExtraTerm>& terms = ExtraTerms();
  for (std::size_t i = 0; i < terms.size(); ++i) {
    FlagInfo info;
    info.name = terms[i].name;
    info.type = "float";
    info.role = FlagRole::kOption;
    info.help = {{kReconstruct, term_help[i].c_str()}};
    info.full_help = FullHelp(info.help, info.choices);
    info.sets_option = true;
    info.text = [i](const CommandFlags& flags) {
      return FormatDouble(flags.term_weights[i]);
    };
    info.set_text = [i, flag = info.name](const std::string& text,
                                          CommandFlags* flags) {
      return ParseFlagText(flag, text, &flags->term_weights[i]);
    };
    // 0 leaves the term out of the problem.
    info.apply = [i, term = info.name](const CommandFlags& flags,
                                       FlagTargets* targets) {
      if (flags.term_weights[i] != 0.0) {
        targets->reconstruct.problem.term_weights[term] = flags.term_weights[i];
      }
      return Status::OK();
    };
    table.push_back(std::move(info));
  }
  return table;
}

}  // namespace

Status ParseNumBasesFlag(const std::string& value, NumBasesFlag* num_bases) {
  *num_bases = NumBasesFlag();
  if (value.empty()) return Status::OK();
  num_bases->given = true;
  num_bases->automatic = value == "auto";
  if (num_bases->automatic) return Status::OK();
  if (!ParseInt(value, &num_bases->value) || num_bases->value < 1) {
    *num_bases = NumBasesFlag();
    return Status::Error("must be an integer >= 1 or 'auto', got '" + value +
                         "'");
  }
  return Status::OK();
}

Status ParseIntrinsicsFlag(const std::string& text,
                           Eigen::Matrix4Xd* intrinsics) {
  if (text.empty()) {
    intrinsics->resize(4, 0);
    return Status::OK();
  }
  return ParseIntrinsics(text, intrinsics);
}

Status ParseHeldBlocks(const std::string& list, ProblemOptions* options) {
  const std::pair<const char*, bool ProblemOptions::*> kinds[] = {
      {"rotations", &ProblemOptions::constant_rotations},
      {"translations", &ProblemOptions::constant_translations},
      {"weights", &ProblemOptions::constant_weights},
      {"basis", &ProblemOptions::constant_basis},
      {"scales", &ProblemOptions::constant_scales},
      {"rig", &ProblemOptions::constant_rig}};
  std::size_t begin = 0;
  while (begin < list.size()) {
    std::size_t end = list.find(',', begin);
    if (end == std::string::npos) end = list.size();
    const std::string name = list.substr(begin, end - begin);
    bool found = false;
    for (const auto& kind : kinds) {
      if (name == kind.first) {
        options->*kind.second = true;
        found = true;
      }
    }
    if (!found) {
      std::string valid;
      for (const auto& kind : kinds)
        valid += (valid.empty() ? "" : ", ") + std::string(kind.first);
      return UnknownName("kind of block", name, valid);
    }
    begin = end + 1;
  }
  return Status::OK();
}

Status FlagTargets::CheckParts() const {
  NRSFM_RETURN_IF_ERROR(input.keypoints.Check());
  NRSFM_RETURN_IF_ERROR(input.Check());
  NRSFM_RETURN_IF_ERROR(reconstruct.start.Check());
  NRSFM_RETURN_IF_ERROR(reconstruct.problem.Check());
  NRSFM_RETURN_IF_ERROR(reconstruct.solver.Check());
  NRSFM_RETURN_IF_ERROR(reconstruct.prior_rule.Check());
  NRSFM_RETURN_IF_ERROR(track.Check());
  NRSFM_RETURN_IF_ERROR(uncertainty.options.Check());
  return select.Check();
}

Status FlagTargets::Check() const {
  NRSFM_RETURN_IF_ERROR(input.Check());
  NRSFM_RETURN_IF_ERROR(reconstruct.Check());
  NRSFM_RETURN_IF_ERROR(track.Check());
  NRSFM_RETURN_IF_ERROR(uncertainty.options.Check());
  return select.Check();
}

const char* CommandName(Command command) {
  switch (command) {
    case kReconstruct:
      return "reconstruct";
    case kEvaluate:
      return "evaluate";
    case kSynth:
      return "synth";
    case kView:
      return "view";
    case kTrack:
      return "track";
  }
  return "";
}

bool FlagInfo::Serves(Command command) const {
  for (const CommandHelp& part : help) {
    if ((part.commands & command) != 0) return true;
  }
  return false;
}

std::string FlagInfo::HelpFor(Command command) const {
  std::string out;
  for (const CommandHelp& part : help) {
    if ((part.commands & command) != 0) {
      out += (out.empty() ? "" : " ") + ChoicesPrefix(choices) +
             std::string(part.text);
    }
  }
  return out;
}

const std::vector<FlagInfo>& CommandFlagTable() {
  static const std::vector<FlagInfo> table = MakeTable();
  return table;
}

const FlagInfo* FindFlag(const std::string& name) {
  for (const FlagInfo& flag : CommandFlagTable()) {
    if (flag.name == name) return &flag;
  }
  return nullptr;
}

std::string TermFlagHelp(const ExtraTerm& term) {
  return std::string("weight of the ") + term.meaning + "; " + term.units +
         ", 0 = off (docs/problem.md).";
}

Status ApplyFlags(const CommandFlags& flags, FlagTargets* targets) {
  *targets = FlagTargets();
  for (const FlagInfo& flag : CommandFlagTable()) {
    if (!flag.sets_option) continue;
    // The library judges the value alone, so that the error names the flag.
    FlagTargets alone;
    NRSFM_RETURN_IF_ERROR(
        flag.apply(flags, &alone).WithContext("--" + flag.name));
    NRSFM_RETURN_IF_ERROR(alone.CheckParts().WithContext("--" + flag.name));
    NRSFM_RETURN_IF_ERROR(flag.apply(flags, targets));
  }
  // A weight given on the command line is a manual choice of the terms.
  if (!targets->reconstruct.problem.term_weights.empty()) {
    targets->reconstruct.priors = PriorMode::kManual;
  }
  return targets->Check();
}

Status SetFlagFromText(const std::string& name, const std::string& text,
                       CommandFlags* flags) {
  const FlagInfo* flag = FindFlag(name);
  if (flag == nullptr) return Status::Error("unknown option '" + name + "'");
  return flag->set_text(text, flags);
}

std::vector<std::pair<std::string, std::string>> OptionList(
    const CommandFlags& flags, int num_bases) {
  std::vector<std::pair<std::string, std::string>> list = {
      {"K", std::to_string(num_bases)}, {"K_flag", flags.K}};
  for (const FlagInfo& flag : CommandFlagTable()) {
    switch (flag.role) {
      case FlagRole::kInput:
      case FlagRole::kWeights:
      case FlagRole::kStart:
      case FlagRole::kOption:
        list.emplace_back(flag.name, flag.text(flags));
        break;
      case FlagRole::kNumBases:
      case FlagRole::kSynthesis:
      case FlagRole::kTracking:
      case FlagRole::kTool:
        break;
    }
  }
  return list;
}

}  // namespace tools
}  // namespace nrsfm
