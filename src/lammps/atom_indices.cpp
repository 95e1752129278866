// Each atom's engine index and caller's id: see atom_indices.hpp.
#ifdef PFILL_WITH_LAMMPS
#include "lammps/atom_indices.hpp"

#include <algorithm>

namespace pfill {
namespace lammps_engine {

const char* atom_index_fix() { return "fix pf_indices all property/atom i_pfindex d_pfid ghost no\n"; }

AtomIndices::AtomIndices(const LammpsSession& s)
    : index(s.atoms<int*>("i_pfindex")), id(s.atoms<double*>("d_pfid")), count(s.nlocal()) {}

std::vector<std::pair<size_t, int>> own_by_index(const LammpsSession& s) {
  const AtomIndices a(s);
  std::vector<std::pair<size_t, int>> own(static_cast<size_t>(a.count));
  for (int i = 0; i < a.count; ++i) own[static_cast<size_t>(i)] = {static_cast<size_t>(a.index[i]), i};
  std::sort(own.begin(), own.end());
  return own;
}

}  // namespace lammps_engine
}  // namespace pfill
#endif
