// A batch of births handed to LAMMPS: see new_atoms.hpp.
#ifdef PFILL_WITH_LAMMPS
#include "lammps/new_atoms.hpp"

#include <algorithm>
#include <numeric>

#include "lammps/atom_indices.hpp"

namespace pfill {
namespace lammps_engine {
namespace {

constexpr size_t kPacked = 10;  // tag, x, v, radius, mass, id (below 2^53)

bool inside(const SubDomain& d, const double* x) {
  for (int a = 0; a < 3; ++a)
    if (!(x[a] >= d.lo[a] && x[a] < d.hi[a])) return false;
  return true;
}

}  // namespace

void NewAtoms::add(int tag, const Particle& p, double m) {
  tags.push_back(tag);
  x.insert(x.end(), {p.position.x, p.position.y, p.position.z});
  v.insert(v.end(), {p.velocity.x, p.velocity.y, p.velocity.z});
  radius.push_back(p.radius);
  mass.push_back(m);
  ids.push_back(p.id);
}

void NewAtoms::sort_by_tag() {
  if (std::is_sorted(tags.begin(), tags.end())) return;
  std::vector<size_t> order(size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::sort(order.begin(), order.end(), [this](size_t a, size_t b) { return tags[a] < tags[b]; });
  NewAtoms sorted;
  for (size_t k : order) {
    sorted.tags.push_back(tags[k]);
    sorted.x.insert(sorted.x.end(), {x[3 * k], x[3 * k + 1], x[3 * k + 2]});
    sorted.v.insert(sorted.v.end(), {v[3 * k], v[3 * k + 1], v[3 * k + 2]});
    sorted.radius.push_back(radius[k]);
    sorted.mass.push_back(mass[k]);
    sorted.ids.push_back(ids[k]);
  }
  *this = std::move(sorted);
}

size_t outside_subdomain(const LammpsSession& s, const NewAtoms& atoms) {
  const SubDomain d = s.subdomain();
  size_t n = 0;
  for (size_t k = 0; k < atoms.size(); ++k) n += inside(d, &atoms.x[3 * k]) ? 0 : 1;
  return n;
}

size_t share_strays(const LammpsSession& s, NewAtoms& atoms) {
  if (s.ranks() == 1) return 0;
  // The usual case: the sub-domains have not moved since the births were decided.
  int any = static_cast<int>(outside_subdomain(s, atoms));
  MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_MAX, s.comm());
  if (any == 0) return 0;
  const SubDomain d = s.subdomain();
  NewAtoms kept;
  std::vector<double> strays;
  for (size_t k = 0; k < atoms.size(); ++k) {
    const double *x = &atoms.x[3 * k], *v = &atoms.v[3 * k];
    if (inside(d, x)) {
      kept.tags.push_back(atoms.tags[k]);
      kept.x.insert(kept.x.end(), x, x + 3), kept.v.insert(kept.v.end(), v, v + 3);
      kept.radius.push_back(atoms.radius[k]), kept.mass.push_back(atoms.mass[k]), kept.ids.push_back(atoms.ids[k]);
    } else {
      strays.insert(strays.end(), {static_cast<double>(atoms.tags[k]), x[0], x[1], x[2], v[0], v[1], v[2],
                                   atoms.radius[k], atoms.mass[k], static_cast<double>(atoms.ids[k])});
    }
  }
  const size_t sent = strays.size() / kPacked;
  const std::vector<double> all = s.gather(strays);
  for (size_t k = 0; k + kPacked <= all.size(); k += kPacked) {
    const double* a = &all[k];
    kept.tags.push_back(static_cast<int>(a[0]));
    kept.x.insert(kept.x.end(), a + 1, a + 4), kept.v.insert(kept.v.end(), a + 4, a + 7);
    kept.radius.push_back(a[7]), kept.mass.push_back(a[8]), kept.ids.push_back(static_cast<uint64_t>(a[9]));
  }
  kept.sort_by_tag();
  atoms = std::move(kept);
  return sent;
}

int create_new_atoms(LammpsSession& s, const NewAtoms& atoms, int first_tag, size_t first_index) {
  const int before = s.nlocal();
  const int made = s.create_atoms(atoms.tags, atoms.x, atoms.v);
  // Radius, mass, index and id of the new atoms this rank owns (create_atoms gives 0.5 and density 1).
  const int after = s.nlocal();
  int* tag = s.atoms<int*>("id");
  double* radius = s.atoms<double*>("radius");
  double* rmass = s.atoms<double*>("rmass");
  const AtomIndices own(s);
  for (int i = before; i < after; ++i) {
    const size_t k = static_cast<size_t>(std::lower_bound(atoms.tags.begin(), atoms.tags.end(), tag[i]) -
                                         atoms.tags.begin());
    radius[i] = atoms.radius[k];
    rmass[i] = atoms.mass[k];
    own.index[i] = static_cast<int>(first_index + static_cast<size_t>(tag[i] - first_tag));
    own.id[i] = static_cast<double>(atoms.ids[k]);
  }
  return made;
}

}  // namespace lammps_engine
}  // namespace pfill
#endif
