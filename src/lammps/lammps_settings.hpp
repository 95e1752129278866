// What the LAMMPS engine hands LAMMPS before any atom (docs/lammps_engine.md
// "The physics, mapped onto LAMMPS"): the parameters it refuses, in one
// line and before LAMMPS could stop the program on them; and the box, the
// pair style whose list the callback walks, the neighbour lists and the
// callback's fix, as LAMMPS commands.
#pragma once
#ifdef PFILL_WITH_LAMMPS
#include <string>

#include "lammps/lammps_session.hpp"
#include "pfill/engine/params.hpp"
#include "pfill/vec3.hpp"

namespace pfill {
namespace lammps_engine {

/// The engine's constants; then refuses, in one line and before LAMMPS is
/// started, what LAMMPS cannot run as pfill's engine does.
EngineConstants checked_constants(const EngineParams& params);

/// What set_up_box chose.
struct BoxSettings {
  Box3 box;                                     ///< LAMMPS' box: the inner box and a margin
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};  ///< atoms are clamped into this, a little inside `box`
  std::string describe;                         ///< the engine's line on its potential and lists
};

/// The box LAMMPS decomposes (`inner`, the field's box or the given one,
/// and a margin), the potential, the lists and `fix external pf/callback`
/// as `fix_id`, handed to `lmp` (collective).
BoxSettings set_up_box(LammpsSession& lmp, const EngineParams& params, const EngineConstants& c, const Box3& inner,
                       const char* fix_id);

}  // namespace lammps_engine
}  // namespace pfill
#endif
