// A 64-bit word sent among doubles (ids, packed colours) and back, bit for
// bit: the processes' messages of the finish and the exact check are rows
// of doubles (finish_view.cpp, particle_share.cpp).
#pragma once
#include <cstdint>
#include <cstring>

namespace pfill {

inline uint64_t bits_of(double x) {
  uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

inline double double_of(uint64_t b) {
  double x;
  std::memcpy(&x, &b, sizeof x);
  return x;
}

}  // namespace pfill
