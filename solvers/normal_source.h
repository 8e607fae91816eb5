// Standard normal draws for the seeded random parts of the solvers (the
// rigid start's initial weights, coarse-to-fine's new weights, the corrective
// triple's starts): mt19937_64 with our own Box-Muller transform (one value
// per pair of draws), so the sequence does not depend on the standard
// library's std::normal_distribution and is the same on every platform.
#ifndef NRSFM_SOLVERS_NORMAL_SOURCE_H_
#define NRSFM_SOLVERS_NORMAL_SOURCE_H_

#include <cmath>
#include <cstdint>
#include <random>

namespace nrsfm {

class NormalSource {
 public:
  explicit NormalSource(std::uint64_t seed) : engine_(seed) {}
  double Next() {
    constexpr double kTwoPi = 6.283185307179586;
    const double u1 =
        (static_cast<double>(engine_() >> 11) + 1.0) * 0x1.0p-53;  // (0, 1]
    const double u2 = static_cast<double>(engine_() >> 11) * 0x1.0p-53;
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(kTwoPi * u2);
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_NORMAL_SOURCE_H_
