// Writing one record per particle in chunks, so that memory stays small
// for millions of particles (shared by the PLY and CSV writers).
#pragma once
#include <algorithm>
#include <cstddef>
#include <string>

#include "pfill/atomic_file.hpp"

namespace pfill {

/// Calls append(buffer, i) for i = 0..count-1, flushing the buffer to `file`
/// every `chunk` records.
template <class Append>
void write_records(AtomicFile& file, size_t count, size_t chunk, Append&& append) {
  std::string buffer;
  for (size_t begin = 0; begin < count; begin += chunk) {
    buffer.clear();
    const size_t end = std::min(count, begin + chunk);
    for (size_t i = begin; i < end; ++i) append(buffer, i);
    file.write(buffer);
  }
}

}  // namespace pfill
