// float32 values in [0, 1] -> unsigned samples for the LDR writers (bakeshop/io/_quantize.py).
#pragma once

#include "common/kernel.hpp"

namespace bakeshop::io {

// rint(p) for 0 <= p < 2**23 under the default rounding (to nearest, ties to even): p + 2**23
// lies where float32's step is 1, so the addition rounds p to an integer, and the subtraction
// is exact. (std::rint is a libm call on x86-64 without SSE4.1's roundss.)
inline float round_even(float p) {
  constexpr float shift = 8388608.0f;  // 2**23
  return (p + shift) - shift;
}

// out[i] = rint(clip(values[i], 0, 1) * top) (the float32 product, rounded to nearest even),
// NaN -> 0, in one pass; T is uint8_t or uint16_t and top its largest value.
template <class T>
void quantize(const float* values, index_t size, T top, T* out) {
  const float scale = static_cast<float>(top);
#pragma omp parallel for schedule(static)
  for (index_t i = 0; i < size; ++i) {
    const float v = values[i];
    if (!(v > 0))  // NaN, zero and negatives
      out[i] = 0;
    else if (v >= 1)
      out[i] = top;
    else
      out[i] = static_cast<T>(round_even(v * scale));
  }
}

}  // namespace bakeshop::io
