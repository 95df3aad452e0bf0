// The seeded amplitudes of an ocean's lattice modes (bakeshop/water/amplitudes.py): SplitMix64
// of the seed and each mode's integer indices, then Box-Muller.
#pragma once

#include <cmath>
#include <cstdint>

#include "common/kernel.hpp"

namespace bakeshop::water {

inline uint64_t splitmix64(uint64_t z) {
  z = z + 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// Two standard normals per mode (mx[i], my[i]) into out[i, 0:2] (serial: a handful of modes).
inline void mode_normals(uint64_t seed, const int64_t* mx, const int64_t* my, index_t count,
                         double* out) {
  const uint64_t base = splitmix64(seed);
  const double scale = std::ldexp(1.0, -53);
  const double two_pi = 2.0 * M_PI;
  for (index_t i = 0; i < count; ++i) {
    uint64_t state = splitmix64(base ^ static_cast<uint64_t>(mx[i]));
    // int64 product wrapping as the old JIT's (done unsigned: signed overflow is undefined in C++)
    state = splitmix64(state ^ (static_cast<uint64_t>(my[i]) * 0x5851F42Dull));
    const double u1 = (static_cast<double>(splitmix64(state) >> 11) + 0.5) * scale;
    double u2 = static_cast<double>(splitmix64(state ^ 0xD1B54A32D192ED03ull) >> 11) + 0.5;
    u2 *= scale;
    const double r = std::sqrt(-2.0 * std::log(u1));
    out[2 * i] = r * std::cos(two_pi * u2);
    out[2 * i + 1] = r * std::sin(two_pi * u2);
  }
}

}  // namespace bakeshop::water
