// FIRE on the LAMMPS engine (EngineParams::fire; Bitzek et al., PRL 97,
// 170201, 2006): the state kernels/physics.cl's pf_fire_next keeps, run as
// the OpenCL engine and the C++ reference (src/engine/reference.cpp) run
// it, so that the three give the same trajectory. Each step the callback
// moves this rank's atoms by pf_fire_kick_drift with this state's dt,
// alpha and restart; the step's power P = sum F.v is over ALL atoms, so
// end_step sums it over the ranks, and every rank then updates the same
// state from the same P: dt, alpha, the steps since P <= 0 and the
// restarts stay identical on every rank without being sent.
//
// The OpenCL engine knows a step's P two steps late (the record of step t
// sets the state of step t + 3; the records still in flight are taken in
// when the history is read, the particles sorted, or FIRE restarted or
// read). LAMMPS could take P in at once; it keeps the same lag so that its
// steps are the reference's, which the tests check, and the finish's FIRE
// settings, tuned on the OpenCL engine, hold unchanged.
#pragma once
#ifdef PFILL_WITH_LAMMPS
#include <cstdint>
#include <utility>
#include <vector>

#include "lammps/lammps_session.hpp"
#include "pfill/engine/particle_engine.hpp"

namespace pfill {
namespace lammps_engine {

class FireMinimiser {
 public:
  /// Off (and every call a no-op) unless params.fire.on; starts as restart(0).
  FireMinimiser(const EngineParams& params, const EngineConstants& constants, const LammpsSession& session);

  bool on() const { return on_; }
  double dt() const { return dt_; }
  double alpha() const { return alpha_; }
  /// At a restart, each centre moves back by this times its velocity.
  double backtrack() const { return backtrack_; }
  /// Whether the step of this index (the engine's, from 0) restarts: velocities dropped.
  bool restarts_at(uint64_t step) const { return on_ && restart_step_ == static_cast<uint32_t>(step); }

  /// After the step of index `step`, whose power on this rank's atoms was
  /// `mine`: returns P over all ranks (collective: each rank at each step;
  /// summed in rank order, the same bits everywhere) and takes in the
  /// record of step - 2 (for the steps from step + 1 on), as the OpenCL
  /// engine's step does.
  double end_step(uint64_t step, double mine);
  /// Takes in every record in flight, oldest first, for the steps from
  /// `steps_done` on (no communication: every rank holds the same).
  void take_in_flight(uint64_t steps_done);
  /// Afresh at the step of index `steps_done`: the first dt, alpha_start,
  /// every velocity dropped there, the restarts counted from 0.
  void restart(uint64_t steps_done);
  /// dt, alpha and the restarts, after take_in_flight; zeros when off.
  ParticleEngine::MinimiserState state() const;

 private:
  /// The state after one record (physics.cl pf_fire_next).
  void take_in(uint64_t record_step, double power, uint64_t effect_step);

  bool on_ = false;
  FireParams rule_;
  double first_dt_ = 0;
  const LammpsSession& session_;
  double dt_ = 0, alpha_ = 0, backtrack_ = 0, positive_ = 0, restarts_ = 0;
  uint32_t restart_step_ = 0;  // as physics.cl keeps it (uint)
  std::vector<std::pair<uint64_t, double>> in_flight_;  // (step, P) of records not yet taken in
  std::vector<double> powers_;                          // each rank's share of a step's P
};

}  // namespace lammps_engine
}  // namespace pfill
#endif
