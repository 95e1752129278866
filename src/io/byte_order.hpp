// Little-endian encoding of numbers for the binary writers, independent of
// the host's byte order.
#pragma once
#include <cstdint>
#include <cstring>
#include <string>

namespace pfill {
namespace byte_order {

inline void append_u32_le(std::string& out, uint32_t v) {
  const char bytes[4] = {static_cast<char>(v & 0xff), static_cast<char>((v >> 8) & 0xff),
                         static_cast<char>((v >> 16) & 0xff), static_cast<char>((v >> 24) & 0xff)};
  out.append(bytes, 4);
}

inline void append_u64_le(std::string& out, uint64_t v) {
  append_u32_le(out, static_cast<uint32_t>(v & 0xffffffffu));
  append_u32_le(out, static_cast<uint32_t>(v >> 32));
}

inline void append_f32_le(std::string& out, float f) {
  uint32_t bits;
  std::memcpy(&bits, &f, 4);
  append_u32_le(out, bits);
}

inline void append_f64_le(std::string& out, double d) {
  uint64_t bits;
  std::memcpy(&bits, &d, 8);
  append_u64_le(out, bits);
}

}  // namespace byte_order
}  // namespace pfill
