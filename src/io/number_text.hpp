// Numbers as text for the text particle formats (CSV, LAMMPS data, xyzr).
#pragma once
#include <charconv>
#include <string>

namespace pfill {

/// The shortest decimal form that reads back to the same double (at most
/// max_digits10 = 17 significant digits), so text round trips are exact.
inline void append_number(std::string& out, double v) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
  out.append(buffer, result.ptr);
}

}  // namespace pfill
