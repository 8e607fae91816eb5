// Names of enum values for options, files and the command line: each enum
// has one table {value, name} (in the .cc of the enum's header) and reads
// and writes names through these two functions, e.g.
//   constexpr EnumName<RobustLoss> kRobustLossNames[] = {
//       {RobustLoss::kNone, "none"}, {RobustLoss::kHuber, "huber"}, …};
//   NameOf(kRobustLossNames, RobustLoss::kHuber)            → "huber"
//   ParseName(kRobustLossNames, "tukey", "robust loss", &loss)
//     → error: robust loss: unknown value "tukey" (expected one of none, huber,
//     cauchy)
#ifndef NRSFM_CORE_MODEL_ENUM_NAMES_H_
#define NRSFM_CORE_MODEL_ENUM_NAMES_H_

#include <cstddef>
#include <string>

#include "core/model/status.h"

namespace nrsfm {

template <typename Enum>
struct EnumName {
  Enum value;
  const char* name;
};

// The name of `value` ("unknown" for a value not in the table).
template <typename Enum, std::size_t N>
const char* NameOf(const EnumName<Enum> (&names)[N], Enum value) {
  for (const EnumName<Enum>& entry : names) {
    if (entry.value == value) return entry.name;
  }
  return "unknown";
}

// What an error of ParseName says before the list of names, which ends at
// the next ')': tools read a flag's choices from it (tools/flag_table.h).
inline constexpr char kExpectedOneOf[] = "(expected one of ";

// The error of an unknown name `text` of `what`, listing `valid` ("a, b").
inline Status UnknownName(const std::string& what, const std::string& text,
                          const std::string& valid) {
  return Status::Error(what + ": unknown value \"" + text + "\" " +
                       kExpectedOneOf + valid + ")");
}

// Sets `value` from its name; the error names `what` and lists every name.
template <typename Enum, std::size_t N>
Status ParseName(const EnumName<Enum> (&names)[N], const std::string& text,
                 const std::string& what, Enum* value) {
  std::string valid;
  for (const EnumName<Enum>& entry : names) {
    if (text == entry.name) {
      *value = entry.value;
      return Status::OK();
    }
    valid += (valid.empty() ? "" : ", ") + std::string(entry.name);
  }
  return UnknownName(what, text, valid);
}

}  // namespace nrsfm

#endif  // NRSFM_CORE_MODEL_ENUM_NAMES_H_
