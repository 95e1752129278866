// The LAMMPS engine's births per rank, counted: see birth_tally.hpp.
#include "lammps/birth_tally.hpp"

namespace pfill {
namespace lammps_engine {

BirthTally& birth_tally() {
  static BirthTally tally;
  return tally;
}

}  // namespace lammps_engine
}  // namespace pfill
