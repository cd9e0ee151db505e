// Counter-based random numbers: every draw is a pure function of (seed, stream, counter, index), so a
// scenario's trajectory does not depend on the policy, the order of evaluation or the thread count.
#pragma once
#include <cmath>
#include <cstdint>
#include <numbers>

namespace semlb::rng {

inline uint64_t mix(uint64_t x) {  // SplitMix64 finaliser
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

inline uint64_t bits(uint64_t seed, uint64_t stream, uint64_t counter, uint64_t index = 0) {
  return mix(mix(mix(mix(seed) ^ stream) ^ counter) ^ index);
}

// Uniform in [0, 1) from the top 53 bits.
inline double uniform(uint64_t seed, uint64_t stream, uint64_t counter, uint64_t index = 0) {
  return static_cast<double>(bits(seed, stream, counter, index) >> 11) * 0x1.0p-53;
}

inline double uniform(double lo, double hi, uint64_t seed, uint64_t stream, uint64_t counter, uint64_t index = 0) {
  return lo + (hi - lo) * uniform(seed, stream, counter, index);
}

// Standard normal (Box-Muller on two counter draws).
inline double normal(uint64_t seed, uint64_t stream, uint64_t counter, uint64_t index = 0) {
  const double u1 = 1.0 - uniform(seed, stream, counter, 2 * index);  // (0, 1]
  const double u2 = uniform(seed, stream, counter, 2 * index + 1);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

// Standard normal clipped at 3 sigma: the draw of every multiplicative noise and spread.
inline double clipped_normal(uint64_t seed, uint64_t stream, uint64_t counter, uint64_t index = 0) {
  const double z = normal(seed, stream, counter, index);
  return z < -3.0 ? -3.0 : (z > 3.0 ? 3.0 : z);
}

}  // namespace semlb::rng
