#include "problems/problem_options.h"

#include <cmath>

#include "core/model/enum_names.h"
#include "core/model/option_checker.h"
#include "problems/extra_terms.h"

namespace nrsfm {
namespace {

constexpr EnumName<RobustLoss> kRobustLossNames[] = {
    {RobustLoss::kNone, "none"},
    {RobustLoss::kHuber, "huber"},
    {RobustLoss::kCauchy, "cauchy"},
};

}  // namespace

const char* RobustLossName(RobustLoss loss) {
  return NameOf(kRobustLossNames, loss);
}

Status ParseRobustLoss(const std::string& name, RobustLoss* loss) {
  return ParseName(kRobustLossNames, name, "robust loss", loss);
}

double ProblemOptions::TermWeight(const std::string& name) const {
  const auto found = term_weights.find(name);
  return found == term_weights.end() ? 0.0 : found->second;
}

Status ProblemOptions::Check() const {
  OptionChecker check("problem options");
  check.FinitePositive("robust_scale", robust_scale);
  check.Require(
      observation_weights.size() == 0 || (observation_weights.allFinite() &&
                                          (observation_weights >= 0.0).all()),
      "observation_weights must be finite and non-negative");
  for (const auto& [name, weight] : term_weights) {
    if (FindExtraTerm(name) == nullptr) {
      std::string known;
      for (const ExtraTerm& term : ExtraTerms()) {
        known += (known.empty() ? "" : ", ") + std::string(term.name);
      }
      check.Require(false, "term_weights: no term \"" + name +
                               "\" (the terms are " + known + ")");
    }
    check.FiniteAtLeast("term weight " + name, weight, 0.0);
  }
  check.Nested(smoothness_edges.Check());
  check.Require(
      !(constant_rotations && constant_translations && constant_weights &&
        constant_basis && constant_scales),
      "nothing to refine: every constant_* flag of the data term is true");
  return check.status();
}

}  // namespace nrsfm
