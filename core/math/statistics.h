// Order statistics shared by the pipeline's measurements, the metrics and
// the uncertainty's summary.
#ifndef NRSFM_CORE_MATH_STATISTICS_H_
#define NRSFM_CORE_MATH_STATISTICS_H_

#include <vector>

namespace nrsfm {

// The upper median of `values`: the element at index n / 2 of the sorted
// values (for an even count the larger of the two middle ones, so the
// result is always one of the values), found in O(n) by std::nth_element.
// `if_empty` when there are none. NaN values have no defined order: the
// caller removes them first.
double UpperMedian(std::vector<double> values, double if_empty);

}  // namespace nrsfm

#endif  // NRSFM_CORE_MATH_STATISTICS_H_
