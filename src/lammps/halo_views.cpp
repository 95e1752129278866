// What a rank sees of the others' atoms at P > 1 ranks: see halo_views.hpp.
#ifdef PFILL_WITH_LAMMPS
#include "lammps/halo_views.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "lammps/atom_indices.hpp"

namespace pfill {
namespace lammps_engine {
namespace {

/// Every rank's sub-domain, in rank order (one MPI_Allgather).
std::vector<Box3> all_subdomains(const LammpsSession& s) {
  const SubDomain d = s.subdomain();
  const double mine[6] = {d.lo[0], d.lo[1], d.lo[2], d.hi[0], d.hi[1], d.hi[2]};
  std::vector<double> all(6 * static_cast<size_t>(s.ranks()));
  MPI_Allgather(mine, 6, MPI_DOUBLE, all.data(), 6, MPI_DOUBLE, s.comm());
  std::vector<Box3> boxes(static_cast<size_t>(s.ranks()));
  for (size_t r = 0; r < boxes.size(); ++r) {
    const double* b = &all[6 * r];
    boxes[r].lo = {b[0], b[1], b[2]};
    boxes[r].hi = {b[3], b[4], b[5]};
  }
  return boxes;
}

/// How far p lies inside box b (0 outside it).
double depth_in(const Box3& b, const Vec3& p) {
  const double d = std::min({p.x - b.lo.x, b.hi.x - p.x, p.y - b.lo.y, b.hi.y - p.y, p.z - b.lo.z, b.hi.z - p.z});
  return std::max(d, 0.0);
}

/// The gap between two boxes (0 where they touch or overlap).
double gap(const Box3& a, const Box3& b) {
  const double dx = std::max({a.lo.x - b.hi.x, b.lo.x - a.hi.x, 0.0});
  const double dy = std::max({a.lo.y - b.hi.y, b.lo.y - a.hi.y, 0.0});
  const double dz = std::max({a.lo.z - b.hi.z, b.lo.z - a.hi.z, 0.0});
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

/// x, y, z, radius (and, with `tags_and_ids`, the tag and the id) of each own atom within
/// `reach` of another rank's sub-domain, per rank. Atoms deeper than
/// `reach` inside this rank's own sub-domain are no other rank's concern
/// (the sub-domains tile the box).
std::vector<std::vector<double>> outgoing(const LammpsSession& s, const std::vector<Box3>& boxes, double reach,
                                          bool tags_and_ids) {
  const int nl = s.nlocal(), me = s.rank();
  double** x = s.atoms<double**>("x");
  double* radius = s.atoms<double*>("radius");
  int* tag = s.atoms<int*>("id");
  const AtomIndices own(s);
  // Atoms may have left the sub-domain since LAMMPS' last exchange: the
  // ranks near any of them, from the box of the sub-domain and its atoms.
  Box3 spread = boxes[static_cast<size_t>(me)];
  for (int i = 0; i < nl; ++i) spread.add({x[i][0], x[i][1], x[i][2]});
  std::vector<int> near;
  for (int r = 0; r < s.ranks(); ++r)
    if (r != me && gap(spread, boxes[static_cast<size_t>(r)]) <= reach) near.push_back(r);
  std::vector<std::vector<double>> out(static_cast<size_t>(s.ranks()));
  for (int i = 0; i < nl; ++i) {
    const Vec3 p{x[i][0], x[i][1], x[i][2]};
    if (depth_in(boxes[static_cast<size_t>(me)], p) > reach) continue;
    for (int r : near)
      if (distance_to_box(boxes[static_cast<size_t>(r)], p) <= reach) {
        std::vector<double>& o = out[static_cast<size_t>(r)];
        o.insert(o.end(), {p.x, p.y, p.z, radius[i]});
        if (tags_and_ids) o.insert(o.end(), {static_cast<double>(tag[i]), own.id[i]});
      }
  }
  return out;
}

/// Each rank's `out[r]` to rank r (MPI_Alltoall of the counts, then MPI_Alltoallv).
std::vector<double> exchange_rows(const LammpsSession& s, const std::vector<std::vector<double>>& out) {
  const size_t ranks = static_cast<size_t>(s.ranks());
  std::vector<int> send_n(ranks), recv_n(ranks), send_at(ranks, 0), recv_at(ranks, 0);
  std::vector<double> send;
  for (size_t r = 0; r < ranks; ++r) {
    send_at[r] = static_cast<int>(send.size());
    send_n[r] = static_cast<int>(out[r].size());
    send.insert(send.end(), out[r].begin(), out[r].end());
  }
  MPI_Alltoall(send_n.data(), 1, MPI_INT, recv_n.data(), 1, MPI_INT, s.comm());
  for (size_t r = 1; r < ranks; ++r) recv_at[r] = recv_at[r - 1] + recv_n[r - 1];
  std::vector<double> got(static_cast<size_t>(recv_at.back() + recv_n.back()));
  MPI_Alltoallv(send.data(), send_n.data(), send_at.data(), MPI_DOUBLE, got.data(), recv_n.data(), recv_at.data(),
                MPI_DOUBLE, s.comm());
  return got;
}

}  // namespace

BirthView birth_halo(const LammpsSession& s, double reach) {
  BirthView view;
  view.regions = all_subdomains(s);
  view.region = s.rank();
  const std::vector<double> got = exchange_rows(s, outgoing(s, view.regions, reach, false));
  const int nl = s.nlocal();
  double** x = s.atoms<double**>("x");
  double* radius = s.atoms<double*>("radius");
  view.centres.reserve(static_cast<size_t>(nl) + got.size() / 4);
  view.radii.reserve(view.centres.capacity());
  for (int i = 0; i < nl; ++i) view.centres.push_back({x[i][0], x[i][1], x[i][2]}), view.radii.push_back(radius[i]);
  view.own = static_cast<size_t>(nl);
  for (size_t k = 0; k + 3 < got.size(); k += 4)
    view.centres.push_back({got[k], got[k + 1], got[k + 2]}), view.radii.push_back(got[k + 3]);
  return view;
}

LocalView local_halo(const LammpsSession& s, const EngineParams& params, double reach) {
  LocalView view;
  view.regions = all_subdomains(s);
  view.region = s.rank();
  const std::vector<double> got = exchange_rows(s, outgoing(s, view.regions, reach, true));
  int* tag = s.atoms<int*>("id");
  double** x = s.atoms<double**>("x");
  double** v = s.atoms<double**>("v");
  double* radius = s.atoms<double*>("radius");
  const AtomIndices ids(s);
  // Own atoms in the order of the engine's indices: the same decisions
  // whatever order LAMMPS keeps them in.
  const std::vector<std::pair<size_t, int>> own = own_by_index(s);
  view.own = own.size();
  view.particles.reserve(own.size() + got.size() / 6);
  for (const auto& [index, i] : own) {
    Particle p;
    p.position = {x[i][0], x[i][1], x[i][2]};
    p.velocity = {v[i][0], v[i][1], v[i][2]};
    p.radius = radius[i];
    p.mass = particle_mass(params, p.radius);
    p.id = ids.id_of(i);
    view.particles.push_back(p);
    view.indices.push_back(index);
    view.keys.push_back(static_cast<uint64_t>(tag[i]));
  }
  for (size_t k = 0; k + 5 < got.size(); k += 6) {
    Particle p;
    p.position = {got[k], got[k + 1], got[k + 2]};
    p.radius = got[k + 3];
    p.mass = particle_mass(params, p.radius);
    p.id = static_cast<uint64_t>(got[k + 5]);
    view.particles.push_back(p);
    view.keys.push_back(static_cast<uint64_t>(got[k + 4]));
  }
  return view;
}

}  // namespace lammps_engine
}  // namespace pfill
#endif
