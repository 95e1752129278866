// Embree's errors as pfill's: Embree reports them through a C callback,
// which must not throw, so the first message is kept and thrown after the
// Embree call returns.
#pragma once
#include <embree3/rtcore.h>

#include <mutex>
#include <string>

namespace pfill {

struct EmbreeErrorLog {
  std::mutex mutex;
  std::string first;  ///< the first error's message ("" for none)

  std::string first_message() {
    std::lock_guard<std::mutex> lock(mutex);
    return first;
  }
};

/// Embree's name for an error code.
const char* embree_error_name(RTCError code);

/// The callback for rtcSetDeviceErrorFunction, with an EmbreeErrorLog as `user`.
void record_embree_error(void* user, RTCError code, const char* message);

}  // namespace pfill
