/// @file particle_engine.hpp
/// @brief What the fill asks of an engine: particles in, steps, records
/// and particles out. The OpenCL Engine (engine.hpp) and the C++
/// reference (reference.hpp) both implement it, so the fill's passes run
/// on either (FillOptions::engine); the reference needs no OpenCL device.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pfill/engine/birth_view.hpp"
#include "pfill/engine/params.hpp"
#include "pfill/engine/process_group.hpp"
#include "pfill/error.hpp"
#include "pfill/engine/step_record.hpp"
#include "pfill/grid.hpp"
#include "pfill/vec3.hpp"

namespace pfill {

struct LocalView;  // local_view.hpp

/// One particle as the host sees it.
struct Particle {
  Vec3 position;
  Vec3 velocity;   ///< on read-back: the half-step velocity of the last step
  double radius = 0;
  double mass = 0; ///< 0 on add: derived from the radius (particle_mass)
  uint64_t id = 0; ///< the caller's label; the engine keeps it with the particle (removals, sorts)
};

class ExactField;  // pfill/exact_field.hpp

class ParticleEngine {
 public:
  virtual ~ParticleEngine() = default;

  virtual const EngineParams& params() const = 0;
  virtual const EngineConstants& constants() const = 0;
  /// One line naming the engine and what it chose for itself.
  virtual std::string describe() const = 0;

  /// The wall: a signed distance grid (negative inside, dims >= 2 each).
  virtual void set_field(const ScalarGrid& field) = 0;
  /// As set_field, but the engine may read `field` in place instead of a
  /// copy (then `field` must stay unchanged and outlive the engine).
  virtual void share_field(const ScalarGrid& field) { set_field(field); }
  /// Bytes this process holds of the wall's field for the engine (the
  /// LAMMPS engine: its bricks near the wall); 0 when it reads the
  /// caller's field in place.
  virtual size_t field_bytes() const { return 0; }
  /// The wall computed from the mesh where the engine's particles reach it
  /// (`field` must outlive the engine): no whole grid held. Engines that
  /// cannot (all but the LAMMPS engine) throw pfill::Error.
  virtual void share_exact_field(const ExactField& field) {
    (void)field;
    throw Error(describe() + " needs the wall's field as a grid in memory (share_field)");
  }
  /// Appends particles; returns the index of the first.
  virtual size_t add_particles(const std::vector<Particle>& particles) = 0;
  size_t add_particle(const Particle& p) { return add_particles({p}); }
  /// Appends a batch of `count` particles split over the processes that
  /// share this engine (issue 31: births, the finish's hand-over and its
  /// newcomers). `mine` holds the members this process decided (its
  /// BirthView or LocalView), with their ids; `places[k]` is mine[k]'s
  /// place in the batch, each place given by exactly one process. The batch
  /// gets consecutive indices in the order of its places; returns the
  /// first. No process is given the whole batch's ids. One process (the
  /// default): `mine` is the whole batch.
  virtual size_t add_decided_particles(const std::vector<Particle>& mine, const std::vector<size_t>& places,
                                       size_t count);
  /// Removes particles by index, largest first, each swapped with the last.
  virtual void remove_particles(std::vector<size_t> indices) = 0;
  /// Runs (or enqueues) k steps.
  virtual void run_steps(size_t k) = 0;
  /// The records of every step since the last call.
  virtual std::vector<StepRecord> read_history() = 0;
  /// All particles: positions, velocities, radii, masses, ids.
  virtual std::vector<Particle> read_particles() = 0;
  /// Renumbers the particles for locality where the engine gains by it;
  /// returns new index -> old index, or nothing where the indices stay
  /// (an engine that keeps its own order: LAMMPS).
  virtual std::vector<size_t> sort_by_cells() = 0;
  /// Indices of particles flagged outside the field since the last clear_flags().
  virtual std::vector<size_t> flagged_particles() = 0;
  virtual void clear_flags() = 0;

  /// What the births' room test sees here (birth_view.hpp): every particle
  /// within `reach` of the sites this process decides, and which sites
  /// those are. `complete`: every particle and every site, whatever the
  /// process count (the report's schedule of unequal spheres: their births
  /// depend on each other in the sites' order). By default (one process): read_particles, every site.
  virtual BirthView birth_view(double reach, bool complete) {
    (void)reach, (void)complete;
    BirthView view;
    for (const Particle& p : read_particles()) view.centres.push_back(p.position), view.radii.push_back(p.radius);
    view.own = view.centres.size();
    return view;
  }
  /// What the finish decides on here (local_view.hpp): this process's
  /// own particles and every other within `reach` of its sub-domain. By
  /// default (one process): read_particles, every particle its own.
  virtual LocalView local_view(double reach);
  /// Sums `counts` element by element over the processes that share this
  /// engine (each passes as many; collective). One process: unchanged.
  virtual void sum_over_processes(std::vector<int>& counts) { (void)counts; }
  /// Every process's `values`, one after the other in process order, into
  /// `values` on every process (collective; each may pass a different
  /// count). One process: unchanged.
  virtual void gather_over_processes(std::vector<uint64_t>& values) { (void)values; }
  /// The processes that share this engine, for what runs after it is gone
  /// (the fill's exact check, its metrics and output; process_group.hpp).
  /// One process: the group of one.
  virtual std::shared_ptr<ProcessGroup> process_group() const { return std::make_shared<ProcessGroup>(); }
  virtual size_t size() const = 0;          ///< particle count
  virtual uint64_t steps_done() const = 0;  ///< steps run (or enqueued)

  /// A particle's part in the steps while the engine holds some (hold).
  enum class StepPart : uint8_t { moving, held, out };
  /// The finish's last jams relaxed where they are (finish.cpp): until
  /// release_hold, steps move only the particles whose part_of(position)
  /// is moving; held ones stay still and push the moving; the rest take no
  /// part (no step costs them much: their pairs are not looked at, so
  /// part_of must put every one further than a pair's reach,
  /// EngineConstants::list_reach less the skin, from every moving one).
  /// part_of must give the same part for a place on every process (each
  /// asks it of its own particles). Returns
  /// how many move or are held, over every process (collective); nothing
  /// where the engine cannot hold (by default: the finish then relaxes
  /// such a region on an engine of its own).
  virtual std::optional<size_t> hold(const std::function<StepPart(const Vec3&)>& part_of) {
    (void)part_of;
    return std::nullopt;
  }
  /// Every particle moves again (collective).
  virtual void release_hold() {}

  /// FIRE (params().fire.on): the minimiser starts afresh at the next
  /// step (its first dt, alpha at its start, every velocity dropped).
  /// Engines without FIRE ignore it.
  virtual void restart_minimiser() {}
  /// FIRE's state after the steps read so far (for reports; zeros without FIRE).
  struct MinimiserState {
    double dt = 0, alpha = 0;
    double restarts = 0;  ///< since the last restart_minimiser
  };
  virtual MinimiserState minimiser_state() { return {}; }
};

}  // namespace pfill
