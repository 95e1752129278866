// Numbers in the fill's messages: six significant digits, no trailing zeros.
#pragma once
#include <cstdio>
#include <string>

namespace pfill {

inline std::string short_number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

}  // namespace pfill
