/// @file engine.hpp
/// @brief The OpenCL particle engine: owns all particle state on the device
/// and advances it. The fill (birth, removal, stopping tests) drives it
/// through this header only; it never sees OpenCL buffers or kernels.
///
/// Physics (kernels/physics.cl; the steps in kernels/*_step.cl): Lennard-Jones pair
/// forces with exponents (a, b) shifted to zero at the cutoff, inelastic
/// contact impulses between overlapping spheres (restitution), a wall from
/// a signed distance field (negative inside) that keeps every centre at
/// least its radius inside and reflects outward motion (wall restitution),
/// leapfrog integration with optional damping and a speed cap.
///
/// Neighbours: Verlet lists with a skin (EngineParams::skin_sigma), rebuilt
/// on the device from a uniform cell grid whenever a particle has moved half
/// the skin since the last build, and after births, removals and growth.
///
/// Cost model: run_steps(k) enqueues k steps of two launches each (the
/// first, filling the cells, returns at once unless the lists are due) and
/// returns without waiting; per-step scalars stay on the device until
/// read_history() (no blocking read per step). Births of one particle and
/// removals are one tiny launch each; reads (history, particles, flags)
/// block. No allocation per step; buffers grow by doubling on births.
///
/// @note Not thread-safe; two engines may live side by side.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "pfill/engine/params.hpp"
#include "pfill/engine/particle_engine.hpp"
#include "pfill/engine/step_record.hpp"
#include "pfill/grid.hpp"
#include "pfill/vec3.hpp"

namespace pfill {

class Device;

class Engine final : public ParticleEngine {
 public:
  /// Builds the kernels for `params` on `device` (which must outlive the
  /// engine). Throws pfill::Error for a bad setting, DeviceError for OpenCL.
  Engine(Device& device, const EngineParams& params);
  ~Engine();
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  const EngineParams& params() const override;
  const EngineConstants& constants() const override;
  std::string describe() const override;  ///< choices().describe()
  /// The automatic settings as made for the device (resolve_for_device);
  /// choices().describe() is a line saying what they are.
  const DeviceChoices& choices() const;

  /// The wall: a signed distance grid (negative inside, dims >= 2 each).
  /// Its box becomes the neighbour-grid domain. Uploaded once (blocking).
  /// (EngineParams::wall_offset moves the wall in.)
  void set_field(const ScalarGrid& field) override;
  /// As set_field, but on CPU devices, whose memory is the host's, the
  /// device reads `field`'s values in place instead of a copy (up to 256
  /// MiB saved): `field` must then stay unchanged and outlive the engine.
  void share_field(const ScalarGrid& field) override;

  /// Appends particles; returns the index of the first. Radii must be in
  /// (0, max_radius]. One particle is one small launch (no blocking); more
  /// are a blocking upload.
  size_t add_particles(const std::vector<Particle>& particles) override;

  /// Removes particles by index. Each removal moves the current last
  /// particle into the freed index (swap with last); indices are processed
  /// from the largest down, so the other given indices stay valid. Indices
  /// >= size() throw.
  void remove_particles(std::vector<size_t> indices) override;

  /// Where particle `index` is after remove_particles(removed) on an engine
  /// of `count` particles: its new index, or kGone when it was removed.
  static size_t index_after_removal(size_t index, std::vector<size_t> removed, size_t count);
  static constexpr size_t kGone = static_cast<size_t>(-1);

  /// Enqueues k steps and returns at once (no blocking read). Blocks only
  /// when more than history_capacity records are unread (they move to a
  /// host-side backlog, returned by the next read_history).
  void run_steps(size_t k) override;

  /// The records of every step since the last call (blocking).
  std::vector<StepRecord> read_history() override;

  /// All particles (blocking): positions, velocities, radii, masses.
  std::vector<Particle> read_particles() override;

  /// Every particle's centre and radius (blocking): the positions alone,
  /// read into a buffer kept from one wave to the next (the default's
  /// read_particles made ~10,000 page faults a wave at 1e6).
  BirthView birth_view(double reach, bool complete) override;

  /// Renumbers the particles along a Z-order (Morton) curve of the cells
  /// they are in, ties by their current index, so that particles near in
  /// space are near in memory: pair loops then read neighbours from cache.
  /// Every index changes (a flag moves with its particle); the lists are
  /// rebuilt by the next step. Blocking: one read and one write of the
  /// state; worth it after bulk additions and again when the particles
  /// have mixed (a fill of 4,000 renumbered every 1,024 steps ran about
  /// 20% more steps a second on PoCL: the wall's field is read from cache
  /// too). Returns
  /// new index -> old index.
  std::vector<size_t> sort_by_cells() override;

  /// ParticleEngine::hold: the particles taking part are renumbered first
  /// (each part in its order) and stepped alone, the held ones at rest
  /// with a mass of 1e30; the others follow them, untouched. size() and
  /// read_particles() count them all (with their own masses); a sort
  /// renumbers those taking part among themselves; an addition or removal
  /// releases the hold first. The lists are rebuilt at the next step.
  std::optional<size_t> hold(const std::function<StepPart(const Vec3&)>& part_of) override;
  /// Every particle steps again, with its own mass (blocking).
  void release_hold() override;

  /// Indices of particles flagged outside the field since the last
  /// clear_flags() (a flag moves with its particle on removal).
  std::vector<size_t> flagged_particles() override;
  void clear_flags() override;

  size_t size() const override;          ///< particle count
  uint64_t steps_done() const override;  ///< steps enqueued since construction

  /// FIRE: the state written for the next step (after the steps in flight are finished).
  void restart_minimiser() override;
  MinimiserState minimiser_state() override;  ///< (blocking)

  /// Blocks until the device is idle.
  void finish();

  /// For tests: each particle's neighbour indices as the cell list finds
  /// them (pairs with d^2 < max(rc^2, (r_i + r_j)^2)), unsorted. Blocking.
  std::vector<std::vector<uint32_t>> neighbour_lists();
  /// For tests: each particle's neighbour list as the step form's last
  /// step built it (or a birth or removal edited it), in row order; with
  /// Newton's third law (DeviceChoices::newton) each pair is in one of its
  /// two particles' lists. Empty lists before the first step. Blocking.
  std::vector<std::vector<uint32_t>> step_lists();

  /// With a profiling Device: seconds spent in each kernel since the last
  /// call (blocking); empty otherwise.
  std::map<std::string, double> kernel_times();

 private:
  void set_field(const ScalarGrid& field, bool borrow);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pfill
