#include "tools/command_flags.h"

#include <gflags/gflags.h>
#include <glog/logging.h>

#include "tools/flag_options.h"

namespace nrsfm {
namespace tools {
namespace {

// gflags keeps the name, help and both pointers for the life of the program.
template <typename T>
void Register(const char* name, const char* help, T* storage, T* default_storage) {
  gflags::FlagRegisterer(name, help, kCommandFlagsFile, storage, default_storage);
}

}  // namespace

void RegisterCommandFlags(CommandFlags* flags) {
  static bool registered = false;
  CHECK(!registered) << "RegisterCommandFlags called twice";
  registered = true;
  static CommandFlags defaults;  // the default values gflags reports
#define NRSFM_REGISTER_COMMAND_FLAG(type, name, value, help) \
  Register<type>(#name, help, &flags->name, &defaults.name);
  NRSFM_COMMAND_FLAGS(NRSFM_REGISTER_COMMAND_FLAG)
#undef NRSFM_REGISTER_COMMAND_FLAG

  static const std::vector<std::string> term_help = [] {
    std::vector<std::string> help;
    for (const ExtraTerm& term : ExtraTerms()) help.push_back(TermFlagHelp(term));
    return help;
  }();
  const std::vector<ExtraTerm>& terms = ExtraTerms();
  for (std::size_t i = 0; i < terms.size(); ++i) {
    Register<double>(terms[i].name, term_help[i].c_str(), &flags->term_weights[i],
                     &defaults.term_weights[i]);
  }
}

}  // namespace tools
}  // namespace nrsfm
