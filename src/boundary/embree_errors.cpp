// Embree's errors kept for pfill to throw (embree_errors.hpp).
#include "boundary/embree_errors.hpp"

namespace pfill {

const char* embree_error_name(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_UNKNOWN: return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
  }
  return "unrecognised error";
}

void record_embree_error(void* user, RTCError code, const char* message) {
  auto* log = static_cast<EmbreeErrorLog*>(user);
  std::lock_guard<std::mutex> lock(log->mutex);
  if (log->first.empty())
    log->first = std::string(embree_error_name(code)) + (message ? std::string(": ") + message : std::string());
}

}  // namespace pfill
