/// @file peak_memory.hpp
/// @brief The process's peak resident memory, which a fill reports
/// (FillResult::peak_memory): on PoCL the device's buffers are host memory,
/// so this is the whole fill's footprint, device included.
#pragma once
#include <cstddef>

namespace pfill {

/// Peak resident set size of this process so far, in bytes (getrusage's
/// ru_maxrss); 0 where the platform does not say. It includes whatever the
/// process held before the fill (a Python interpreter, a loaded mesh).
size_t peak_resident_bytes();

}  // namespace pfill
