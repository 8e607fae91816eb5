#include "tools/command_flags.h"

#include <gflags/gflags.h>
#include <glog/logging.h>

#include "tools/flag_table.h"

namespace nrsfm {
namespace tools {
namespace {

// gflags keeps the name, help and both pointers for the life of the program.
template <typename T>
void Register(const char* name, const char* help, T* storage,
              T* default_storage) {
  gflags::FlagRegisterer(name, help, kCommandFlagsFile, storage,
                         default_storage);
}

}  // namespace

void RegisterCommandFlags(CommandFlags* flags) {
  static bool registered = false;
  CHECK(!registered) << "RegisterCommandFlags called twice";
  registered = true;
  static CommandFlags defaults;  // the default values gflags reports
  // The rows of CommandFlagTable() are in the order of NRSFM_COMMAND_FLAGS,
  // then the extra terms.
  const std::vector<FlagInfo>& table = CommandFlagTable();
  std::size_t row = 0;
#define NRSFM_REGISTER_COMMAND_FLAG(type, flag, value, role, bind, help) \
  CHECK_EQ(table[row].name, #flag);                                      \
  Register<type>(#flag, table[row++].full_help.c_str(), &flags->flag,    \
                 &defaults.flag);
  NRSFM_COMMAND_FLAGS(NRSFM_REGISTER_COMMAND_FLAG)
#undef NRSFM_REGISTER_COMMAND_FLAG
  for (std::size_t i = 0; i < ExtraTerms().size(); ++i, ++row) {
    Register<double>(table[row].name.c_str(), table[row].full_help.c_str(),
                     &flags->term_weights[i], &defaults.term_weights[i]);
  }
}

}  // namespace tools
}  // namespace nrsfm
