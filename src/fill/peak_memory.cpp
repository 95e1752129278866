// The process's peak resident memory (see include/pfill/peak_memory.hpp).
#include "pfill/peak_memory.hpp"

#if defined(__unix__) || defined(__APPLE__)
#include <sys/resource.h>
#endif

namespace pfill {

size_t peak_resident_bytes() {
#if defined(__unix__) || defined(__APPLE__)
  rusage ru{};
  if (getrusage(RUSAGE_SELF, &ru) != 0 || ru.ru_maxrss < 0) return 0;
#if defined(__APPLE__)
  return static_cast<size_t>(ru.ru_maxrss);  // bytes there
#else
  return static_cast<size_t>(ru.ru_maxrss) * 1024;  // KiB on Linux
#endif
#else
  return 0;
#endif
}

}  // namespace pfill
