// Seeded random numbers that are the same on every platform and build:
// std::mt19937_64 (specified bit for bit by the C++ standard) with our own
// conversions to doubles, since the std distributions are
// implementation-defined. Used by the synthetic generators
// (core/synthetic/synthetic.h) and by the seeded parts of the closed-form
// starts (random initial weights, random starts of the corrective triple).
#ifndef NRSFM_CORE_MATH_RANDOM_H_
#define NRSFM_CORE_MATH_RANDOM_H_

#include <cmath>
#include <cstdint>
#include <random>

namespace nrsfm {

inline constexpr double kTwoPi = 2.0 * 3.14159265358979323846;

// Box–Muller transform: two independent standard normal values from
// u1 ∈ (0, 1] and u2 ∈ [0, 1), r = sqrt(−2 log u1), z0 = r cos(2π u2),
// z1 = r sin(2π u2). `z1` may be null.
inline void BoxMuller(double u1, double u2, double* z0, double* z1) {
  const double radius = std::sqrt(-2.0 * std::log(u1));
  const double angle = kTwoPi * u2;
  *z0 = radius * std::cos(angle);
  if (z1 != nullptr) *z1 = radius * std::sin(angle);
}

class Random {
 public:
  // The engine seeded with `seed` itself.
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  // Stream `stream` of `seed`: the engine seeded with SplitMix64(seed +
  // stream · 0x9E3779B97F4A7C15), so that streams of one seed are
  // independent (the synthetic generators draw geometry, motion, noise and
  // missing entries from separate streams).
  Random(std::uint64_t seed, std::uint64_t stream)
      : engine_(SplitMix64(seed + 0x9E3779B97F4A7C15ULL * stream)) {}

  // Uniform in [0, 1): the top 53 bits of one draw.
  double Uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  // Uniform in {0, …, n − 1} (modulo bias below 2⁻³², irrelevant here).
  int Index(int n) {
    return static_cast<int>(engine_() % static_cast<std::uint64_t>(n));
  }

  // Standard normal values by BoxMuller(). Normal() returns both values of
  // each pair in turn, with u1 = 1 − Uniform(), u2 = Uniform().
  // NormalUnpaired() draws a new pair for every value and keeps z0, with
  // u1 = (bits + 1) · 2⁻⁵³ and u2 = Uniform(). The two give different
  // sequences for one seed: the synthetic data use Normal(), the starts'
  // seeded draws NormalUnpaired(), and each is kept so that neither the data
  // nor the starts change with a seed.
  double Normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - Uniform();
    const double u2 = Uniform();
    double z0 = 0.0;
    BoxMuller(u1, u2, &z0, &spare_);
    has_spare_ = true;
    return z0;
  }
  double NormalUnpaired() {
    const double u1 = (static_cast<double>(engine_() >> 11) + 1.0) * 0x1.0p-53;
    const double u2 = Uniform();
    double z0 = 0.0;
    BoxMuller(u1, u2, &z0, nullptr);
    return z0;
  }

 private:
  static std::uint64_t SplitMix64(std::uint64_t x) {
    x += 0x9E3779B97F4A7C15ULL;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
    return x ^ (x >> 31);
  }

  std::mt19937_64 engine_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace nrsfm

#endif  // NRSFM_CORE_MATH_RANDOM_H_
