// What the BPTC formats' kernels share (bakeshop/io/compress/decode.py, bc6h_signed.py): the
// bits of a 128-bit block and BC6H's endpoint arithmetic (Khronos Data Format spec 1.4, 18).
#pragma once

#include <cstdint>

#include "common/kernel.hpp"

namespace bakeshop::io::compress {

// A 16-byte block as a 128-bit little-endian integer (two 64-bit halves).
class Block128 {
 public:
  explicit Block128(const uint8_t* bytes) {
    for (int k = 0; k < 8; ++k) {
      lo_ |= static_cast<uint64_t>(bytes[k]) << (8 * k);
      hi_ |= static_cast<uint64_t>(bytes[8 + k]) << (8 * k);
    }
  }
  uint64_t low() const { return lo_; }
  // `count` (0..32) bits from bit `position`; position + count <= 128 (the callers' layouts
  // end at bit 128, whatever the block holds).
  int64_t bits(int position, int count) const {
    const uint64_t mask = (uint64_t{1} << count) - 1;
    if (position >= 64) return static_cast<int64_t>((hi_ >> (position - 64)) & mask);
    uint64_t value = lo_ >> position;
    if (position + count > 64) value |= hi_ << (64 - position);  // position > 32 here
    return static_cast<int64_t>(value & mask);
  }

 private:
  uint64_t lo_ = 0;
  uint64_t hi_ = 0;
};

// The low `bits` bits of `value`, sign-extended.
inline int64_t sign_extend(int64_t value, int bits) {
  value &= (int64_t{1} << bits) - 1;
  return ((value >> (bits - 1)) & 1) ? value - (int64_t{1} << bits) : value;
}

// The spec's unsigned unquantisation of a BC6H endpoint of `bits` bits (x >= 0).
inline int64_t unquantize_unsigned(int64_t x, int bits) {
  if (bits >= 15 || x == 0) return x;
  if (x == (int64_t{1} << bits) - 1) return 0xFFFF;
  return ((x << 15) + 0x4000) >> (bits - 1);
}

// The spec's signed unquantisation of a BC6H endpoint of `bits` bits: the decoder's and the
// signed encoder's (one definition).
inline int64_t unquantize_signed(int64_t x, int bits) {
  if (bits >= 16) return x;
  const bool negative = x < 0;
  if (negative) x = -x;
  int64_t unq;
  if (x == 0)
    unq = 0;
  else if (x >= (int64_t{1} << (bits - 1)) - 1)
    unq = 0x7FFF;
  else
    unq = ((x << 15) + 0x4000) >> (bits - 1);
  return negative ? -unq : unq;
}

// BPTC's interpolation of two endpoints with a weight of 0..64.
inline int64_t interpolate(int64_t e0, int64_t e1, int64_t w) {
  return ((64 - w) * e0 + w * e1 + 32) >> 6;  // >> of a negative: arithmetic (as Python's)
}

}  // namespace bakeshop::io::compress
