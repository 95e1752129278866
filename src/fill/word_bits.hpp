// A double sent among 64-bit words and back, bit for bit: the processes'
// messages of the finish and the exact check are rows of doubles carrying
// ids and packed colours (finish_view.cpp, particle_share.cpp); the birth
// sites' are rows of words carrying places (held_sites.cpp, site_verdicts.hpp).
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
