#include "core/model/option_checker.h"

#include <cmath>
#include <sstream>

namespace nrsfm {
namespace {

std::string Format(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

}  // namespace

void OptionChecker::AtLeast(const std::string& field, double value,
                            double min) {
  if (!(value >= min)) Fail(field, value, "must be >= " + Format(min));
}

void OptionChecker::FiniteAtLeast(const std::string& field, double value,
                                  double min) {
  if (!(std::isfinite(value) && value >= min)) {
    Fail(field, value, "must be finite and >= " + Format(min));
  }
}

void OptionChecker::FinitePositive(const std::string& field, double value) {
  if (!(std::isfinite(value) && value > 0.0)) {
    Fail(field, value, "must be positive and finite");
  }
}

void OptionChecker::InRange(const std::string& field, double value, double lo,
                            double hi, bool hi_open) {
  if (!(value >= lo && (hi_open ? value < hi : value <= hi))) {
    Fail(field, value,
         "must be in [" + Format(lo) + ", " + Format(hi) +
             (hi_open ? ")" : "]"));
  }
}

void OptionChecker::Require(bool condition, const std::string& message) {
  if (status_.ok() && !condition)
    status_ = Status::Error(what_ + ": " + message);
}

void OptionChecker::Nested(const Status& status) {
  if (status_.ok() && !status.ok()) status_ = status.WithContext(what_);
}

void OptionChecker::Fail(const std::string& field, double value,
                         const std::string& rule) {
  if (!status_.ok()) return;  // report the first problem
  status_ = Status::Error(what_ + ": " + field + " " + rule + ", got " +
                          Format(value));
}

}  // namespace nrsfm
