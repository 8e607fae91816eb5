// The one way option structs validate themselves (every Check() of the
// library): the rules are applied in turn and the first that fails gives the
// error "<what>: <field> <rule>, got <value>", e.g.
//   "solver options: max_iterations must be >= 0, got -1".
// NaN fails every numeric rule.
#ifndef NRSFM_CORE_MODEL_OPTION_CHECKER_H_
#define NRSFM_CORE_MODEL_OPTION_CHECKER_H_

#include <string>
#include <utility>

#include "core/model/status.h"

namespace nrsfm {

class OptionChecker {
 public:
  // `what` names the options in the message ("solver options").
  explicit OptionChecker(std::string what) : what_(std::move(what)) {}

  void AtLeast(const std::string& field, double value,
               double min);  // value ≥ min
  void FiniteAtLeast(const std::string& field, double value,
                     double min);                               // and finite
  void FinitePositive(const std::string& field, double value);  // 0 < value < ∞
  // lo ≤ value ≤ hi, or lo ≤ value < hi with `hi_open`.
  void InRange(const std::string& field, double value, double lo, double hi,
               bool hi_open = false);
  // Any other rule: fails with "<what>: <message>" unless `condition`.
  void Require(bool condition, const std::string& message);
  // A nested struct's Check(), its message prefixed with "<what>: ".
  void Nested(const Status& status);

  // OK, or the first failure.
  const Status& status() const { return status_; }

 private:
  void Fail(const std::string& field, double value, const std::string& rule);

  std::string what_;
  Status status_;
};

}  // namespace nrsfm

#endif  // NRSFM_CORE_MODEL_OPTION_CHECKER_H_
