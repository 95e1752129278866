// The settings handed to LAMMPS: see lammps_settings.hpp.
#ifdef PFILL_WITH_LAMMPS
#include "lammps/lammps_settings.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "lammps/atom_indices.hpp"
#include "pfill/error.hpp"

namespace pfill {
namespace lammps_engine {
namespace {

/// LAMMPS bins each rank's sub-domain (and its ghost shell) for the
/// lists at `bin` (list_bin_size), and stops the program past 2^31 - 1
/// bins on a rank ("Too many neighbor bins", unseen under -screen none).
/// The sub-domains tile the box, so some rank has at least the box's
/// bins over P: past the limit, that rank would stop. Refused here in one
/// line instead (a box far larger than the spheres: about 2e9 purely
/// repulsive spheres in a mesh's box at P = 1, 3e8 with a cutoff).
void refuse_too_many_bins(const Vec3& size, double bin, int ranks) {
  const double bins = std::floor(size.x / bin) * std::floor(size.y / bin) * std::floor(size.z / bin);
  const double per_rank = bins / ranks;
  if (per_rank > 2147483647.0) {
    char b[64];
    std::snprintf(b, sizeof b, "%.3g", per_rank);
    throw Error("lammps engine: the box would need " + std::string(b) +
                " neighbour-list bins a rank, past LAMMPS' limit of 2^31 - 1; use more MPI ranks, or larger "
                "spheres (fewer of them) for this mesh");
  }
}

void refuse_no_box(const Box3& inner) {
  const double in_lo[3] = {inner.lo.x, inner.lo.y, inner.lo.z}, in_hi[3] = {inner.hi.x, inner.hi.y, inner.hi.z};
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(in_lo[a]) || !std::isfinite(in_hi[a]) || in_lo[a] > in_hi[a])
      throw Error("lammps engine: the domain " + num(in_lo[0]) + "," + num(in_lo[1]) + "," + num(in_lo[2]) +
                  " to " + num(in_hi[0]) + "," + num(in_hi[1]) + "," + num(in_hi[2]) +
                  " is not a box (finite, lo <= hi on each axis)");
}

/// The lists' bins: LAMMPS' default is half the list's reach (a stencil of
/// ~93 bins), made for the usual 2.5 sigma cutoffs, whose bins hold many
/// atoms. Purely repulsive, the reach is ~1.6 sigma and a half-size bin
/// holds half an atom: visiting ~93 nearly empty bins per atom cost more
/// than the distances. Bins of the whole reach (27 bins, ~4 atoms each)
/// built pass 1's lists at 1e5 in 16.6-16.8 ms instead of 20.8-22.3
/// (docs/lammps_engine.md, "Pass 1's lists in bins of the reach").
double list_bin_size(const EngineParams& params, double reach) {
  return params.cutoff_sigma > 0 ? 0.5 * reach : reach;
}

}  // namespace

EngineConstants checked_constants(const EngineParams& params) {
  EngineConstants constants = derive_constants(params);
  const double a = params.exponent_a, b = params.exponent_b;
  if (!(a == 12 && b == 6) && !(a > b && b > 0)) throw Error("lammps engine: exponents must satisfy a > b > 0");
  return constants;
}

BoxSettings set_up_box(LammpsSession& lmp, const EngineParams& params, const EngineConstants& c, const Box3& inner,
                       const char* fix_id) {
  refuse_no_box(inner);
  const Vec3 s = inner.size();
  const double margin = 2 * c.list_reach + 1e-3 * std::max({s.x, s.y, s.z});
  const Vec3 lo = inner.lo - Vec3{margin, margin, margin}, hi = inner.hi + Vec3{margin, margin, margin};
  BoxSettings out;
  out.box = Box3{lo, hi};
  // Atoms are clamped a little inside the box (LAMMPS drops atoms on or past a fixed boundary).
  const double in = 0.25 * margin;
  out.lo[0] = lo.x + in, out.lo[1] = lo.y + in, out.lo[2] = lo.z + in;
  out.hi[0] = hi.x - in, out.hi[1] = hi.y - in, out.hi[2] = hi.z - in;
  std::ostringstream cmd;
  cmd.precision(17);
  cmd << "units lj\natom_style sphere\natom_modify map hash\nboundary f f f\n"
      // Ghosts' velocities only for the contact dashpot (none in the finish's FIRE relaxations).
      << (c.dashpot > 0 ? "comm_modify vel yes\n" : "")
      << "newton off\n"
      << "region pf_box block " << lo.x << " " << hi.x << " " << lo.y << " " << hi.y << " " << lo.z << " " << hi.z
      // Three types: every atom is of the first, but while the engine holds
      // some (step_callback.hpp's kHeldType, kOutType).
      << "\ncreate_box 3 pf_box\n"
      << atom_index_fix();
  // The pair forces are pfill's own (the callback, over this style's list,
  // in one pass with the dashpot): with `newton off` a pair across ranks is
  // listed on both, so each rank applies it to its own atom without a
  // reverse communication. `zero` builds the list to the cutoff plus the
  // skin and computes nothing.
  // Unequal spheres: to the largest pair's reach (its scaled cutoff and contact, or touching).
  const double pairs = c.polydisperse ? std::max(c.list_reach - c.skin, c.contact_distance * c.max_radius / params.radius)
                                      : c.cutoff;
  cmd << "pair_style zero " << num(pairs) << "\npair_coeff * *\n";
  const double skin = (params.skin_sigma > 0 ? params.skin_sigma : kCpuFormSkinSigma) * c.sigma;
  const double bin = list_bin_size(params, pairs + skin);
  refuse_too_many_bins(hi - lo, bin, lmp.ranks());
  cmd << "neighbor " << num(skin) << " bin\nneigh_modify delay 0 every 1 check yes binsize " << num(bin) << "\n"
      << "fix " << fix_id << " all external pf/callback 1 1\n"
      << "timestep " << num(c.dt) << "\n"
      << "thermo_style custom step\nthermo 0\nthermo_modify lost ignore norm no\n";
  out.describe = "pfill's pair forces and contact dashpot in the callback over LAMMPS' lists (pair_style zero), skin " +
                 num(skin / c.sigma) + " sigma";
  lmp.commands(cmd.str());
  return out;
}

}  // namespace lammps_engine
}  // namespace pfill
#endif
