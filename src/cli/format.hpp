// Small text-formatting helpers shared by the subcommands.
#pragma once
#include <cstdio>
#include <string>

namespace pfill::cli {

/// 1234567 -> "1,234,567": counts users read at a glance.
inline std::string thousands(unsigned long long n) {
  std::string digits = std::to_string(n), out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

/// A number with `sig` significant digits, in the shortest of %g forms.
inline std::string num(double v, int sig = 6) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", sig, v);
  return buf;
}

}  // namespace pfill::cli
