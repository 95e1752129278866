// The LAMMPS engine's step callback: see step_callback.hpp.
#ifdef PFILL_WITH_LAMMPS
#include "lammps/step_callback.hpp"
#include "lammps/fma_clones.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "../../kernels/physics_double.hpp"

namespace pfill {
namespace lammps_engine {
namespace {

// physics.cl's wall push and reflection, over the field in bricks.
using namespace physics;
#define PF_FN inline
#define PF_WALL_ITERATIONS kWallIterations
#define PF_SAMPLE_BAND(PX, PY, PZ, G, LANES) field.sample(PX, PY, PZ, G)
PF_DEFINE_WALL_PUSH(band_wall_push, double, int, PF_ANY1, PF_SAMPLE_BAND, pf_wall_velocity_change, BandField& field)
#undef PF_SAMPLE_BAND
#undef PF_WALL_ITERATIONS
#undef PF_FN

}  // namespace

void StepCallback::install(const char* fix_id) {
  lammps_set_fix_external_callback(
      session_.handle(), fix_id,
      [](void* self, int64_t step, int n, int* ids, double** x, double** f) {
        static_cast<StepCallback*>(self)->on_step(step, n, ids, x, f);
      },
      this);
}

void StepCallback::set_clamp(const double lo[3], const double hi[3]) {
  for (int a = 0; a < 3; ++a) lo_[a] = lo[a], hi_[a] = hi[a];
}

void StepCallback::set_field(const ScalarGrid& f, double offset, bool atoms_exist) {
  // Bricks deeper than two of the largest radii: no sphere there reaches the wall.
  set_band_field(std::make_unique<BandField>(f, offset, 2 * constants_.max_radius), atoms_exist);
}

void StepCallback::set_field(const ExactField& f, double offset, bool atoms_exist) {
  set_band_field(std::make_unique<BandField>(f, offset, 2 * constants_.max_radius), atoms_exist);
}

void StepCallback::set_band_field(std::unique_ptr<BandField> field, bool atoms_exist) {
  field_ = std::move(field);
  lipschitz_ = field_->lipschitz();
  // Bounds kept from another field mean nothing: every atom samples the new one first.
  if (atoms_exist && session_.nlocal() > 0) {
    double** omega = session_.atoms<double**>("omega");
    for (int i = 0; i < session_.nlocal(); ++i) omega[i][0] = 0, omega[i][1] = -1;
  }
}

std::vector<LocalRecord> StepCallback::take_history() { return std::exchange(local_history_, {}); }

PFILL_FMA_CLONES void StepCallback::on_step(int64_t step, int nlocal, int* tags, double** x, double** fext) {
  for (int i = 0; i < nlocal; ++i) fext[i][0] = fext[i][1] = fext[i][2] = 0;
  // `run` calls the fixes' setup too (post_force at the run's first
  // step number): that is no step.
  if (step <= static_cast<int64_t>(run_start_)) return;
  const EngineConstants& c = constants_;
  double** v = session_.atoms<double**>("v");
  double* radius = session_.atoms<double*>("radius");
  double* rmass = session_.atoms<double*>("rmass");
  double** omega = session_.atoms<double**>("omega");
  LocalRecord rec;
  rec.particles = nlocal;
  rec.colliding_pairs = pair_forces(nlocal, x, v, radius, rmass);
  // LAMMPS' step `step` is the engine's step step - 1 (the first run's first is 1).
  const uint64_t index = static_cast<uint64_t>(step) - 1;
  const bool fire = fire_.on(), restart = fire_.restarts_at(index);
  // FIRE: a step's move stays within the cap, whatever its dt (the kernels' PF_STEP_CAP / dt).
  const double fire_cap = fire ? c.max_speed * c.dt / fire_.dt() : 0;
  double power = 0;  // FIRE: sum F.v over this rank's atoms at the step's start
  // The wall's reads miss the cache: ahead of the loop, the corners in the
  // brick each atom last read (omega[j][1]) where it may read again.
  const double reach = field_ ? lipschitz_ * c.max_speed * c.dt : 0;  // (every step moves within the cap)
  const int* type = session_.atoms<int*>("type");
  const bool holding = holding_;
  auto ahead = [&](int j) {
    if (j < nlocal && (!holding || type[j] == kMovingType) && omega[j][0] + reach >= -radius[j])
      field_->prefetch(x[j][0], x[j][1], x[j][2], static_cast<int32_t>(omega[j][1]));
  };
  for (int i = 0; i < nlocal; ++i) {
    if (field_) ahead(i + 8);
    if (holding && type[i] != kMovingType) {
      v[i][0] = v[i][1] = v[i][2] = 0;  // held or out: still
      continue;
    }
    double u[3] = {v[i][0], v[i][1], v[i][2]};
    double p[3] = {x[i][0], x[i][1], x[i][2]};
    const double p0[3] = {p[0], p[1], p[2]};
    const double* F = &force_[3 * static_cast<size_t>(i)];
    if (fire) {
      double pi = 0;
      physics::pf_fire_kick_drift(&u[0], &u[1], &u[2], &p[0], &p[1], &p[2], F[0], F[1], F[2], 1 / rmass[i],
                                  fire_.dt(), fire_.alpha(), restart, fire_.backtrack(), fire_cap, &pi);
      power += pi;
    } else {
      physics::pf_kick_drift(&u[0], &u[1], &u[2], &p[0], &p[1], &p[2], F[0], F[1], F[2], 1 / rmass[i], c.dt,
                             c.damping_factor, c.max_speed);
    }
    if (field_) wall(tags[i], p, p0, u, radius[i], omega[i], rec);
    // Never past the box (LAMMPS would lose the atom): the wall brings it back.
    for (int a = 0; a < 3; ++a) p[a] = std::min(std::max(p[a], lo_[a]), hi_[a]);
    x[i][0] = p[0], x[i][1] = p[1], x[i][2] = p[2];
    v[i][0] = u[0], v[i][1] = u[1], v[i][2] = u[2];
    rec.kinetic_energy += 0.5 * rmass[i] * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    rec.max_speed = std::max(rec.max_speed, std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]));
    const double d[3] = {p[0] - p0[0], p[1] - p0[1], p[2] - p0[2]};
    rec.max_displacement = std::max(rec.max_displacement, std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
  }
  // Every rank, every step (collective under FIRE): P over all atoms, the state's next.
  rec.power = fire_.end_step(index, power);
  local_history_.push_back(rec);
}

PFILL_FMA_CLONES void StepCallback::wall(int tag, double* p, const double* p0, double* u, double radius, double* om,
                        LocalRecord& rec) {
  double& omega = om[0];
  BandField& field = *field_;
  const ScalarGrid& grid = field.grid();
  // omega[i][0] (rotation is not integrated) keeps a bound on the
  // field's value at the atom: its last sample plus the field's slope
  // times the moves since. While that bound says the sphere cannot reach
  // the wall, the field is not read (at N = 16,000 on 1 rank, reading it
  // for every atom was half of a step: cache misses in a 57 MiB grid);
  // the result is the same, as the push and the flag need phi > -r.
  const double moved_bound = omega + lipschitz_ * std::sqrt((p[0] - p0[0]) * (p[0] - p0[0]) +
                                                            (p[1] - p0[1]) * (p[1] - p0[1]) +
                                                            (p[2] - p0[2]) * (p[2] - p0[2]));
  if (moved_bound < -radius) {
    omega = moved_bound;
    return;
  }
  const double gx = (p[0] - grid.origin.x) / grid.spacing, gy = (p[1] - grid.origin.y) / grid.spacing,
               gz = (p[2] - grid.origin.z) / grid.spacing;
  const bool outside_box =
      gx < 0 || gy < 0 || gz < 0 || gx > grid.dims[0] - 1 || gy > grid.dims[1] - 1 || gz > grid.dims[2] - 1;
  double g[3], phi = 0;
  if (outside_box) {
    phi = field.sample(p[0], p[1], p[2], g);
  } else if (int32_t slot = -1; field.sample_unless_deep(p[0], p[1], p[2], g, phi, slot)) {
    om[1] = slot;  // (omega's other components are free: rotation is not integrated)
  } else {
    // In a deep brick the sample is below -band (< -r): no push, no flag, and -band bounds it.
    omega = -2 * constants_.max_radius;
    return;
  }
  if (phi > 0 || outside_box) {
    ++rec.flagged;
    flagged_tags_.insert(tag);
  }
  omega = band_wall_push(&p[0], &p[1], &p[2], &u[0], &u[1], &u[2], phi, g, phi > -radius, radius,
                         params_.wall_restitution, field);
}

/// Over this rank's pair list (`pair_style zero`'s, `newton off`: a pair
/// with a ghost is listed on both its ranks, so each rank applies it to
/// its own atom, with no reverse communication): physics.cl's pair force
/// (the potential, capped, and the contact dashpot, as the reference
/// engine sums them) on this rank's atoms into force_, and the pairs whose
/// spheres overlap (d < r_i + r_j; a pair with a ghost counts half, so the
/// sum over ranks counts it once). One pass over the list: LAMMPS computes
/// no pair force (a second pass over the same list cost as much as this).
/// Positions and velocities are the step's start (ghosts' from this step's
/// communication).
PFILL_FMA_CLONES double StepCallback::pair_forces(int nlocal, double** x, double** v, const double* radius,
                                                   const double* rmass) {
  force_.assign(3 * static_cast<size_t>(nlocal), 0.0);
  void* lmp = session_.handle();
  const int list = lammps_find_pair_neighlist(lmp, "zero", 1, 0, 0);
  if (list < 0) return 0;
  const EngineConstants& c = constants_;
  const double sigma2 = c.sigma * c.sigma, rc2 = c.cutoff * c.cutoff, dmin = 1e-3f * c.sigma;
  const double contact2 = c.contact_distance * c.contact_distance;
  const double a = params_.exponent_a, b = params_.exponent_b, eps = params_.eps;
  const bool damp = c.dashpot > 0;
  // Unequal spheres: each pair's lengths scale with (r_i + r_j) / (2 radius), as on the other engines.
  const double rs_ref = 2 * params_.radius;
  const int* tag = session_.atoms<int*>("id");
  // Holding (set_holding): only pairs with a moving atom; out atoms' lists skipped.
  const int* type = session_.atoms<int*>("type");
  const bool holding = holding_;
  // LAMMPS' per-atom 2-d arrays are one block with row pointers: read by
  // offset, not through the row pointer (one dependent load less a pair).
  const double* X = x[0];
  const double* V = v[0];
  const int n = lammps_neighlist_num_elements(lmp, list);
  double count = 0;
  for (int e = 0; e < n; ++e) {
    int i = 0, nn = 0;
    int* neigh = nullptr;
    lammps_neighlist_element_neighbors(lmp, list, e, &i, &nn, &neigh);
    if (i >= nlocal || (holding && type[i] == kOutType)) continue;
    const bool i_moves = !holding || type[i] == kMovingType;
    const double* xi = X + 3 * static_cast<size_t>(i);
    const double* vi = V + 3 * static_cast<size_t>(i);
    double* fi = &force_[3 * static_cast<size_t>(i)];
    // First the neighbours within a pair's reach, without a branch: about
    // half the list lies in the skin, and a branch on each missed often.
    if (near_.size() < static_cast<size_t>(nn)) near_.resize(static_cast<size_t>(nn));  // (only grows)
    int m = 0;
    for (int k = 0; k < nn; ++k) {
      const int j = neigh[k] & 0x3FFFFFFF;  // NEIGHMASK: special-bond bits off
      const double* xj = X + 3 * static_cast<size_t>(j);
      const double d[3] = {xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]};
      const double d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
      const double rs = radius[i] + radius[j];
      const double q2 = c.polydisperse ? physics::pf_pair_scale2(rs, rs_ref, 1 / (rs_ref * rs_ref)) : 1.0;
      const bool wanted = i_moves || type[j] == kMovingType;  // (holding: a pair needs a moving atom)
      near_[static_cast<size_t>(m)] = j;
      m += static_cast<int>(d2 < std::max(rc2 * q2, rs * rs)) & static_cast<int>(wanted);
    }
    for (int t = 0; t < m; ++t) {
      const int j = near_[static_cast<size_t>(t)];
      const double* xj = X + 3 * static_cast<size_t>(j);
      double d[3] = {xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]};
      double d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
      const double rs = radius[i] + radius[j];
      const double q2 = c.polydisperse ? physics::pf_pair_scale2(rs, rs_ref, 1 / (rs_ref * rs_ref)) : 1.0;
      const double q = c.polydisperse ? physics::pf_pair_scale(rs, rs_ref, 1 / rs_ref) : 1.0;
      const bool mine = j < nlocal;
      physics::pf_apart(&d[0], &d[1], &d[2], &d2, d2 < dmin * dmin, tag[j] > tag[i], dmin);
      double fp =
          physics::pf_lj_force_scale(d2, sigma2 * q2, eps, a, b, c.a_half, c.b_half, rc2 * q2, c.force_cap, q2 * q);
      double fn = 0;  // the dashpot, along n = d / |d|
      if (d2 < std::max(rs * rs, contact2 * q2)) {
        if (d2 < rs * rs) count += mine ? 1 : 0.5;
        if (damp) {
          const double inv_d = 1 / std::sqrt(d2);
          const double* vj = V + 3 * static_cast<size_t>(j);
          const double un = ((vi[0] - vj[0]) * d[0] + (vi[1] - vj[1]) * d[1] + (vi[2] - vj[2]) * d[2]) * inv_d;
          // A held atom is as good as infinitely heavy (finish.cpp's kHeldMass): the moving one's dashpot is a wall's.
          const double inv_mi = i_moves ? 1 / rmass[i] : 0;
          const double inv_mj = !holding || type[j] == kMovingType ? 1 / rmass[j] : 0;
          fn = physics::pf_contact_damping(un, inv_mi, inv_mj, c.dashpot, q) * inv_d;
        }
      }
      fp += fn;
      fi[0] += fp * d[0], fi[1] += fp * d[1], fi[2] += fp * d[2];
      if (mine) {
        double* fj = &force_[3 * static_cast<size_t>(j)];
        fj[0] -= fp * d[0], fj[1] -= fp * d[1], fj[2] -= fp * d[2];
      }
    }
  }
  return count;
}

}  // namespace lammps_engine
}  // namespace pfill
#endif
