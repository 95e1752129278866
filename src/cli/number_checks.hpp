// Validators for numeric options, applied to the text the user typed before
// CLI11 converts it: an unsigned option must not take "-5" (which would wrap
// to 18446744073709551611) nor a value past its type, and a density option
// given explicitly must not be 0 (which would mean "unset").
#pragma once
#include <CLI/CLI.hpp>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace pfill::cli {

/// A whole number in [lo, hi], written as digits only.
inline CLI::Validator whole_number(uint64_t lo, uint64_t hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        const std::string range = std::to_string(lo) + ".." + std::to_string(hi);
        if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
          return "'" + text + "' is not a whole number in " + range;
        errno = 0;
        const unsigned long long v = std::strtoull(text.c_str(), nullptr, 10);
        if (errno == ERANGE || v < lo || v > hi) return text + " is outside " + range;
        return "";
      },
      "INT", "whole_number");
}

/// A finite number > 0.
inline CLI::Validator positive_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !std::isfinite(v) || !(v > 0))
          return "'" + text + "' is not a positive number";
        return "";
      },
      "POSITIVE", "positive_number");
}

/// A finite number in [lo, hi] (CLI11's Range lets NaN through: a NaN
/// threshold could never fail).
inline CLI::Validator number_in(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi) {
          char range[64];
          std::snprintf(range, sizeof range, "%g..%g", lo, hi);
          return "'" + text + "' is not a number in " + range;
        }
        return "";
      },
      "NUMBER", "number_in");
}

}  // namespace pfill::cli
