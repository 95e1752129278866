/// @file error.hpp
/// @brief pfill's exception type. Every message is one line that names the
/// problem and, where there is one, the way out.
#pragma once
#include <cstdio>
#include <stdexcept>
#include <string>

namespace pfill {

/// `text` as a message may show it: control bytes (and DEL) written as
/// \xNN, so a corrupt file cannot drive the terminal, and at most `max`
/// bytes of it, the rest counted ("..." and how many more).
inline std::string excerpt(const std::string& text, size_t max = 40) {
  std::string out;
  const size_t shown = text.size() > max ? max : text.size();
  for (size_t i = 0; i < shown; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 || c == 0x7F) {
      char code[8];
      std::snprintf(code, sizeof code, "\\x%02X", c);
      out += code;
    } else {
      out += static_cast<char>(c);
    }
  }
  if (shown < text.size()) out += "... (" + std::to_string(text.size() - shown) + " more bytes)";
  return out;
}

class Error : public std::runtime_error {
 public:
  /// Messages quote file names and file contents: whatever they hold, the
  /// message stays one printable line of at most about 600 bytes.
  explicit Error(const std::string& message) : std::runtime_error(excerpt(message, 600)) {}
  explicit Error(const char* message) : Error(std::string(message)) {}
};

/// A long job stopped because its caller asked (FillOptions::cancelled:
/// Ctrl-C in the command line or in Python). Nothing was written.
class Cancelled : public Error {
 public:
  Cancelled() : Error("cancelled") {}
};

}  // namespace pfill
