/// @file reference.hpp
/// @brief The oracle: a plain double-precision C++ version of the engine's
/// step (brute-force O(n^2) pairs, same formulas from kernels/physics.cl,
/// same order of operations). Tests compare the OpenCL engine against it.
#pragma once
#include <vector>

#include "pfill/engine/engine.hpp"
#include "pfill/engine/params.hpp"
#include "pfill/engine/step_record.hpp"
#include "pfill/grid.hpp"

namespace pfill {

class ReferenceEngine {
 public:
  explicit ReferenceEngine(const EngineParams& params);

  void set_field(const ScalarGrid& field);
  /// Same conventions as Engine::add_particles (mass 0: from the radius).
  void add_particles(const std::vector<Particle>& particles);
  /// Same convention as Engine::remove_particles (swap with last, largest index first).
  void remove_particles(std::vector<size_t> indices);
  /// One step; returns its record.
  StepRecord step();

  const std::vector<Particle>& particles() const { return particles_; }
  const std::vector<bool>& flags() const { return flags_; }
  const EngineConstants& constants() const { return constants_; }

  /// Total pair energy sum over pairs of u(d) (shifted LJ) of the current positions.
  double potential_energy() const;
  /// Brute-force neighbour indices with the engine's criterion, sorted.
  std::vector<std::vector<uint32_t>> neighbour_lists() const;

 private:
  EngineParams params_;
  EngineConstants constants_;
  std::vector<Particle> particles_;
  std::vector<bool> flags_;
  ScalarGrid field_;
  bool has_field_ = false;
  uint64_t steps_ = 0;
};

}  // namespace pfill
