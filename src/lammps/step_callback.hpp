// The LAMMPS engine's step (docs/lammps_engine.md "The physics, mapped onto
// LAMMPS"): the callback of `fix external pf/callback`, called at
// post_force, runs pfill's own rules (kernels/physics.cl in double
// precision) on this rank's atoms: the pair forces (the potential and the
// contact dashpot) over LAMMPS' neighbour list (`pair_style zero`: LAMMPS
// builds the list and computes no force), the kick and
// drift with the damping and the speed cap (or FIRE's step:
// fire_minimiser.hpp), the wall's push from the signed distance field, and
// the per-step records of this rank.
#pragma once
#ifdef PFILL_WITH_LAMMPS
#include <cstdint>
#include <memory>
#include <string>
#include <unordered_set>
#include <vector>

#include "lammps/band_field.hpp"
#include "lammps/fire_minimiser.hpp"
#include "lammps/lammps_session.hpp"
#include "pfill/engine/params.hpp"
#include "pfill/grid.hpp"

namespace pfill {
namespace lammps_engine {

/// The atoms' types while the engine holds some still (StepCallback::set_holding).
constexpr int kMovingType = 1, kHeldType = 2, kOutType = 3;

/// The per-step scalars of one rank, reduced over ranks when read;
/// `power` (FIRE) is already over every rank, the same on each.
struct LocalRecord {
  double kinetic_energy = 0, max_speed = 0, max_displacement = 0;
  double colliding_pairs = 0, flagged = 0, particles = 0;
  double power = 0;
};

class StepCallback {
 public:
  StepCallback(const EngineParams& params, const EngineConstants& constants, LammpsSession& session)
      : params_(params), constants_(constants), session_(session), fire_(params, constants, session) {}
  StepCallback(const StepCallback&) = delete;
  StepCallback& operator=(const StepCallback&) = delete;

  /// Hands this object to the fix external `fix_id` as its callback.
  void install(const char* fix_id);
  /// Atoms are clamped into [lo, hi] after each step (LAMMPS drops atoms past its box).
  void set_clamp(const double lo[3], const double hi[3]);
  /// The field of the wall (it must outlive the callback), moved in by
  /// `offset` (EngineParams::wall_offset, added to each sample as the
  /// kernels add it); with `atoms_exist`, this rank's atoms' kept bounds on
  /// the field are reset, so each samples the new one.
  void set_field(const ScalarGrid& field, double offset, bool atoms_exist);
  /// As set_field, the wall's samples computed from `field` where this rank's atoms reach it.
  void set_field(const ExactField& field, double offset, bool atoms_exist);
  /// Bytes of the field's bricks this rank holds.
  size_t field_bytes() const { return field_ ? field_->bytes() : 0; }
  /// The step number a `run` starts at: its set-up calls the callback at that step, which is no step.
  void set_run_start(uint64_t step) { run_start_ = step; }

  /// This rank's records since the last call.
  std::vector<LocalRecord> take_history();
  /// This rank's atoms flagged outside since they were last cleared.
  std::unordered_set<int>& flagged_tags() { return flagged_tags_; }
  /// FIRE's state (EngineParams::fire; off without it), the same on every rank.
  FireMinimiser& fire() { return fire_; }
  /// While holding, an atom's LAMMPS type says its part in a step
  /// (ParticleEngine::hold_all_but_near): kMovingType atoms step as ever;
  /// kHeldType ones stay still and push the moving; kOutType ones take no
  /// part. Not holding, every atom moves whatever its type.
  void set_holding(bool on) { holding_ = on; }
  bool holding() const { return holding_; }

  void on_step(int64_t step, int nlocal, int* tags, double** x, double** fext);

 private:
  double pair_forces(int nlocal, double** x, double** v, const double* radius, const double* rmass);
  /// The wall on atom i at p (moved from p0, velocity u): the push, the
  /// flag, and in its omega (`om`) the bound on the field there and the brick last read.
  void wall(int tag, double* p, const double* p0, double* u, double radius, double* om, LocalRecord& rec);

  const EngineParams& params_;
  const EngineConstants& constants_;
  LammpsSession& session_;
  void set_band_field(std::unique_ptr<BandField> field, bool atoms_exist);

  std::unique_ptr<BandField> field_;  // null: no wall
  double lipschitz_ = 2;  // the field interpolant's largest slope
  double lo_[3] = {0, 0, 0}, hi_[3] = {0, 0, 0};
  uint64_t run_start_ = 0;
  std::vector<LocalRecord> local_history_;
  std::vector<double> force_;             // the pair forces (potential and dashpot) on this rank's atoms, this step
  std::vector<int> near_;                 // pair_forces: an atom's neighbours within a pair's reach
  std::unordered_set<int> flagged_tags_;  // this rank's atoms flagged outside since clear_flags
  FireMinimiser fire_;
  bool holding_ = false;
};

}  // namespace lammps_engine
}  // namespace pfill
#endif
