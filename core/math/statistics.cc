#include "core/math/statistics.h"

#include <algorithm>

namespace nrsfm {

double UpperMedian(std::vector<double> values, double if_empty) {
  if (values.empty()) return if_empty;
  const auto middle = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace nrsfm
