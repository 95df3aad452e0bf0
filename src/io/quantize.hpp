// float32 values in [0, 1] -> unsigned samples for the LDR writers (bakeshop/io/_quantize.py).
#pragma once

#include <cmath>

#include "common/kernel.hpp"

namespace bakeshop::io {

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
      out[i] = static_cast<T>(std::rint(v * scale));
  }
}

}  // namespace bakeshop::io
