// Seconds since a moment, for the passes' times (FillResult::passes).
#pragma once
#include <chrono>

namespace pfill {

class Stopwatch {
 public:
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace pfill
