/// @file reference.hpp
/// @brief The oracle: a plain double-precision C++ version of the engine's
/// step (brute-force O(n^2) pairs, same formulas from kernels/physics.cl,
/// same order of operations). Tests compare the OpenCL engine against it.
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "pfill/engine/engine.hpp"
#include "pfill/engine/params.hpp"
#include "pfill/engine/step_record.hpp"
#include "pfill/grid.hpp"

namespace pfill {

class ReferenceEngine final : public ParticleEngine {
 public:
  explicit ReferenceEngine(const EngineParams& params);

  void set_field(const ScalarGrid& field) override;
  /// Same conventions as Engine::add_particles (mass 0: from the radius).
  size_t add_particles(const std::vector<Particle>& particles) override;
  /// Same convention as Engine::remove_particles (swap with last, largest index first).
  void remove_particles(std::vector<size_t> indices) override;
  /// One step; returns its record.
  StepRecord step();
  /// A pair's scale squared from its r_i + r_j (physics.cl PF_DEFINE_PAIR_SCALE2; 1 for equal spheres).
  double pair_scale2(double rs) const;
  /// A pair's scale q from its r_i + r_j (physics.cl PF_DEFINE_PAIR_SCALE; 1 for equal spheres):
  /// its energy is q^3 eps, its dashpot keeps the restitution at stiffness q k.
  double pair_scale(double rs) const;

  // ParticleEngine: steps one after the other, their records kept until read.
  const EngineParams& params() const override { return params_; }
  std::string describe() const override;
  void run_steps(size_t k) override;
  std::vector<StepRecord> read_history() override;
  std::vector<Particle> read_particles() override { return particles_; }
  /// The reference lists nothing: the order stays (identity).
  std::vector<size_t> sort_by_cells() override;
  std::vector<size_t> flagged_particles() override;
  void clear_flags() override;
  size_t size() const override { return particles_.size(); }
  uint64_t steps_done() const override { return steps_; }

  /// FIRE as the engine runs it: the state for the next step, and the
  /// records' powers taken in as the engine's steps take them in (the
  /// record of step t in step t + 2; those of steps still in flight when
  /// the history is read, the particles sorted or FIRE restarted, then).
  void restart_minimiser() override;
  MinimiserState minimiser_state() override;

  const std::vector<Particle>& particles() const { return particles_; }
  const std::vector<bool>& flags() const { return flags_; }
  const EngineConstants& constants() const override { return constants_; }

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
  std::vector<StepRecord> history_;  // run_steps' records, until read_history
  struct Fire {  // physics.cl pf_fire_state, for the next step
    double dt = 0, alpha = 0, backtrack = 0, positive = 0, restarts = 0;
    uint32_t restart_step = 0;
  } fire_;
  std::vector<std::pair<uint64_t, double>> in_flight_;  // (step, power) of records FIRE has not taken in
  void take_in_flight();             // takes them all in, oldest first (the engine's finalize_history)
};

}  // namespace pfill
