// A newborn's random draws from a counter-based generator (issue 31):
// the stream is a pure function of (seed, wave, global site index), so the
// same site in the same wave draws the same speed, direction and radius on
// any engine and on any MPI rank that happens to decide that site; no draw
// depends on which other sites were tried before it, or where. The stream
// is splitmix64 (Steele, Lea, Flood 2014) started at a state mixed from the
// three keys: each key goes through splitmix64's finaliser in turn, so
// neighbouring keys (site k and k + 1) start far-apart, uncorrelated streams.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "pfill/vec3.hpp"

namespace pfill {

class CounterRng {
 public:
  using result_type = uint64_t;

  /// The stream of (seed, wave, site); `stream` parts one newborn's draws
  /// by use (0: speed and direction, 1: the radius at the report's
  /// schedule, 2 + c: size class c's radius in a wave), each its own stream.
  CounterRng(uint64_t seed, uint64_t wave, uint64_t site, uint64_t stream = 0)
      : state_(mix(mix(mix(mix(seed) ^ wave) ^ site) ^ stream)) {}

  /// splitmix64's finaliser (a bijection of 64 bits).
  static uint64_t mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }

  /// The next 64 bits (a UniformRandomBitGenerator).
  uint64_t operator()() { return mix(state_ += 0x9e3779b97f4a7c15ULL); }
  static constexpr uint64_t min() { return 0; }
  static constexpr uint64_t max() { return std::numeric_limits<uint64_t>::max(); }

  /// Uniform in [0, 1), 53 bits.
  double uniform() { return static_cast<double>((*this)() >> 11) * 0x1.0p-53; }

  /// A direction uniform on the unit sphere (z uniform in [-1, 1], the
  /// azimuth uniform): two draws, the same on every platform (no
  /// std::normal_distribution, whose algorithm the library chooses).
  Vec3 direction() {
    const double z = 2 * uniform() - 1;
    const double phi = 2 * 3.14159265358979323846 * uniform();
    const double s = std::sqrt(std::max(0.0, 1 - z * z));
    return {s * std::cos(phi), s * std::sin(phi), z};
  }

 private:
  uint64_t state_;
};

}  // namespace pfill
