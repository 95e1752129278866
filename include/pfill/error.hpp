/// @file error.hpp
/// @brief pfill's exception type. Every message is one line that names the
/// problem and, where there is one, the way out.
#pragma once
#include <stdexcept>
#include <string>

namespace pfill {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A long job stopped because its caller asked (FillOptions::cancelled:
/// Ctrl-C in the command line or in Python). Nothing was written.
class Cancelled : public Error {
 public:
  Cancelled() : Error("cancelled") {}
};

}  // namespace pfill
