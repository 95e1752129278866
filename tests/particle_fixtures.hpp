// Particle sets and scratch folders shared by the particle-file and render
// tests.
#pragma once
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "pfill/particles.hpp"

namespace pfill::test {

/// A fresh folder under the system temp folder, removed with its contents.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& tag) {
    std::random_device entropy;
    path_ = std::filesystem::temp_directory_path() /
            ("pfill_" + tag + "_" + std::to_string(entropy()) + std::to_string(entropy()));
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  size_t file_count() const {
    size_t n = 0;
    for (const auto& entry : std::filesystem::directory_iterator(path_)) { (void)entry; ++n; }
    return n;
  }

 private:
  std::filesystem::path path_;
};

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

/// n particles at random positions in [-1, 1]^3 with radii in [0.01, 0.05].
inline ParticleSet random_particles(size_t n, uint32_t seed, bool colours, bool velocities) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0), radius(0.01, 0.05);
  std::uniform_int_distribution<int> channel(0, 255);
  ParticleSet set;
  for (size_t i = 0; i < n; ++i) {
    set.positions.emplace_back(coordinate(rng), coordinate(rng), coordinate(rng));
    set.radii.push_back(radius(rng));
    if (colours)
      set.colours.push_back({uint8_t(channel(rng)), uint8_t(channel(rng)), uint8_t(channel(rng))});
    if (velocities) set.velocities.emplace_back(coordinate(rng), coordinate(rng), coordinate(rng));
  }
  return set;
}

/// Non-overlapping spheres of radius r on a jittered cubic lattice, kept
/// where they lie inside the ball of radius R about the origin.
inline ParticleSet lattice_in_ball(double R, double r, uint32_t seed) {
  std::mt19937 rng(seed);
  const double spacing = 2.2 * r;
  std::uniform_real_distribution<double> jitter(-0.09 * r, 0.09 * r);
  ParticleSet set;
  const int n = static_cast<int>(std::ceil(R / spacing));
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k) {
        const Vec3 p = Vec3(i, j, k) * spacing + Vec3(jitter(rng), jitter(rng), jitter(rng));
        if (length(p) + r <= R) {
          set.positions.push_back(p);
          set.radii.push_back(r);
        }
      }
  return set;
}

}  // namespace pfill::test
