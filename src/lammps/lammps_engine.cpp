// The LAMMPS engine (docs/lammps_engine.md): a ParticleEngine whose
// particles live in a LAMMPS instance on MPI_COMM_WORLD. LAMMPS owns the
// domain decomposition, the neighbour lists, the halo exchange, the
// migration of atoms between ranks and the potential's pair forces (lj/cut,
// or mie/cut, cut at the potential's minimum for the repulsive default);
// pfill's own step rules (kernels/physics.cl, included here in double
// precision as the C++ reference does) run in a `fix external pf/callback`
// on each rank's own atoms: the contact dashpot over LAMMPS' pair list, the
// kick and drift with the damping and the speed cap, then the wall's push
// from the signed distance field, and the per-step records.
//
// SPMD: every rank makes the same calls with the same arguments (the fill's
// host loop runs on every rank), so the engine's bookkeeping of indices and
// ids is the same everywhere; births go to every rank and each keeps those
// in its sub-domain (lammps_create_atoms); reads and records are reductions.
#ifdef PFILL_WITH_LAMMPS
#define LAMMPS_LIB_MPI 1
#ifndef OMPI_SKIP_MPICXX
#define OMPI_SKIP_MPICXX 1
#endif
#include <mpi.h>
#include <library.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <math.h>
#include <sstream>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "pfill/error.hpp"
#include "pfill/lammps.hpp"

namespace pfill {
namespace lammps_physics {
// What physics.cl needs from OpenCL C, in double precision (as src/engine/reference.cpp).
inline int min(int a, int b) { return a < b ? a : b; }
template <class T>
inline T select(T a, T b, int c) {
  return c ? b : a;
}
using ::floor;
using ::fma;
using ::fmax;
using ::fmin;
using ::pow;
using ::sqrt;
#define PF_REAL double
#define PF_FN inline
#define PF_GLOBAL
#include "../../kernels/physics.cl"
#undef PF_REAL
#undef PF_FN
#undef PF_GLOBAL
}  // namespace lammps_physics

namespace {

double sample(const ScalarGrid& f, double x, double y, double z, double* g) {
  return lammps_physics::pf_sdf_sample(f.values.data(), f.dims[0], f.dims[1], f.dims[2], f.origin.x, f.origin.y,
                                       f.origin.z, 1 / f.spacing, x, y, z, g);
}

using lammps_physics::pf_wall_velocity_change;
using lammps_physics::select;
#define PF_FN inline
#define PF_WALL_ITERATIONS kWallIterations
#define PF_SAMPLE_LMP(PX, PY, PZ, G) sample(field, PX, PY, PZ, G)
PF_DEFINE_WALL_PUSH(wall_push, double, int, PF_ANY1, PF_SAMPLE_LMP, pf_wall_velocity_change, const ScalarGrid& field)
#undef PF_FN

bool mpi_started_here = false;

void finalize_mpi() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
}

void ensure_mpi() {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (initialized) return;
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  mpi_started_here = true;
  std::atexit(finalize_mpi);
}

std::string num(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

/// The per-step scalars of one rank, reduced over ranks when read.
struct LocalRecord {
  double kinetic_energy = 0, max_speed = 0, max_displacement = 0;
  double colliding_pairs = 0, flagged = 0, particles = 0;
};

class LammpsEngine final : public ParticleEngine {
 public:
  explicit LammpsEngine(const EngineParams& params) : params_(params), constants_(derive_constants(params)) {
    check_supported();
    ensure_mpi();
    comm_ = MPI_COMM_WORLD;
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &ranks_);
    const char* args[] = {"pfill", "-log", "none", "-screen", "none", "-nocite"};
    lmp_ = lammps_open(6, const_cast<char**>(args), comm_, nullptr);
    if (!lmp_) throw Error("LAMMPS could not be started");
    if (!params_.domain.empty()) make_box(params_.domain);
  }

  ~LammpsEngine() override {
    if (lmp_) lammps_close(lmp_);
  }

  LammpsEngine(const LammpsEngine&) = delete;
  LammpsEngine& operator=(const LammpsEngine&) = delete;

  const EngineParams& params() const override { return params_; }
  const EngineConstants& constants() const override { return constants_; }
  std::string describe() const override {
    return "the LAMMPS engine (LAMMPS " + std::to_string(lammps_version(lmp_)) + ", " + std::to_string(ranks_) +
           " MPI rank" + (ranks_ == 1 ? "" : "s") + "): " + pair_line_;
  }

  void set_field(const ScalarGrid& field) override {
    own_field_ = field;
    // EngineParams::wall_offset: added to each sample as a float, as the kernels read it
    for (float& v : own_field_.values) v += static_cast<float>(params_.wall_offset);
    field_ = &own_field_;
    field_changed();
  }

  void share_field(const ScalarGrid& field) override {
    if (params_.wall_offset != 0) return set_field(field);
    field_ = &field;
    field_changed();
  }

  size_t add_particles(const std::vector<Particle>& ps) override {
    flush();
    const size_t first = order_.size();
    if (ps.empty()) return first;
    if (!box_made_) {
      Box3 b;
      for (const Particle& p : ps) b.add(p.position);
      make_box(b);
    }
    const int n = static_cast<int>(ps.size());
    std::vector<int> tags(ps.size()), types(ps.size(), 1);
    std::vector<double> x(3 * ps.size()), v(3 * ps.size());
    for (size_t k = 0; k < ps.size(); ++k) {
      tags[k] = next_tag_++;
      const Particle& p = ps[k];
      x[3 * k] = p.position.x, x[3 * k + 1] = p.position.y, x[3 * k + 2] = p.position.z;
      v[3 * k] = p.velocity.x, v[3 * k + 1] = p.velocity.y, v[3 * k + 2] = p.velocity.z;
      if (!(p.radius > 0) || p.radius > constants_.max_radius * (1 + 1e-9))
        throw Error("lammps engine: a particle's radius " + num(p.radius) + " is not in (0, max_radius]");
      if (!inside_box(p.position))
        throw Error("lammps engine: a particle at " + num(p.position.x) + "," + num(p.position.y) + "," +
                    num(p.position.z) + " lies outside the engine's box");
    }
    drop_ghosts();
    const int before = nlocal();
    const int made = lammps_create_atoms(lmp_, n, tags.data(), types.data(), x.data(), v.data(), nullptr, 0);
    if (made != n)
      throw Error("lammps engine: " + std::to_string(n) + " particles given, " + std::to_string(made) + " created");
    // Radius and mass of the new atoms this rank owns (create_atoms gives 0.5 and density 1).
    const int after = nlocal();
    int* tag = static_cast<int*>(lammps_extract_atom(lmp_, "id"));
    double* radius = static_cast<double*>(lammps_extract_atom(lmp_, "radius"));
    double* rmass = static_cast<double*>(lammps_extract_atom(lmp_, "rmass"));
    for (int i = before; i < after; ++i) {
      const Particle& p = ps[static_cast<size_t>(tag[i] - tags[0])];
      radius[i] = p.radius;
      rmass[i] = p.mass > 0 ? p.mass : particle_mass(params_, p.radius);
    }
    for (size_t k = 0; k < ps.size(); ++k) {
      index_of_[tags[k]] = order_.size();
      order_.push_back(tags[k]);
      ids_.push_back(ps[k].id);
    }
    dirty_ = true;
    return first;
  }

  void remove_particles(std::vector<size_t> indices) override {
    flush();
    std::sort(indices.begin(), indices.end(), std::greater<size_t>());
    indices.erase(std::unique(indices.begin(), indices.end()), indices.end());
    if (indices.empty()) return;
    std::vector<int> gone;
    for (size_t idx : indices) {
      if (idx >= order_.size()) throw Error("lammps engine: cannot remove particle " + std::to_string(idx));
      const int tag = order_[idx];
      gone.push_back(tag);
      index_of_.erase(tag);
      order_[idx] = order_.back();
      ids_[idx] = ids_.back();
      order_.pop_back();
      ids_.pop_back();
      if (idx < order_.size()) index_of_[order_[idx]] = idx;
    }
    // A group of the ids (in commands of a few hundred), deleted without
    // renumbering: the engine's tags stay.
    std::sort(gone.begin(), gone.end());
    for (size_t k = 0; k < gone.size(); k += 400) {
      std::string cmd = "group pf_gone id";
      for (size_t j = k; j < std::min(gone.size(), k + 400); ++j) cmd += " " + std::to_string(gone[j]);
      command(cmd);
    }
    command("delete_atoms group pf_gone compress no");
    command("group pf_gone delete");
    for (int t : gone) flagged_tags_.erase(t), lost_.erase(t);
    dirty_ = true;
  }

  void run_steps(size_t k) override { pending_ += k; }

  std::vector<StepRecord> read_history() override {
    flush();
    const size_t n = local_history_.size();
    std::vector<double> sums(4 * n), maxes(2 * n);
    for (size_t s = 0; s < n; ++s) {
      const LocalRecord& r = local_history_[s];
      sums[4 * s] = r.kinetic_energy, sums[4 * s + 1] = r.colliding_pairs, sums[4 * s + 2] = r.flagged,
               sums[4 * s + 3] = r.particles;
      maxes[2 * s] = r.max_speed, maxes[2 * s + 1] = r.max_displacement;
    }
    if (ranks_ > 1 && n > 0) {
      MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_DOUBLE, MPI_SUM, comm_);
      MPI_Allreduce(MPI_IN_PLACE, maxes.data(), static_cast<int>(maxes.size()), MPI_DOUBLE, MPI_MAX, comm_);
    }
    std::vector<StepRecord> out(n);
    for (size_t s = 0; s < n; ++s) {
      StepRecord& r = out[s];
      r.step = history_first_ + s;
      r.kinetic_energy = sums[4 * s];
      r.colliding_pairs = static_cast<uint32_t>(sums[4 * s + 1]);
      r.flagged = static_cast<uint32_t>(sums[4 * s + 2]);
      r.particles = static_cast<uint32_t>(sums[4 * s + 3]);
      r.max_speed = maxes[2 * s];
      r.max_displacement = maxes[2 * s + 1];
    }
    history_first_ += n;
    local_history_.clear();
    return out;
  }

  std::vector<Particle> read_particles() override {
    flush();
    // Each rank's own atoms: tag, x, v, radius, mass (8 doubles each), gathered on every rank.
    const int nl = nlocal();
    int* tag = static_cast<int*>(lammps_extract_atom(lmp_, "id"));
    double** x = static_cast<double**>(lammps_extract_atom(lmp_, "x"));
    double** v = static_cast<double**>(lammps_extract_atom(lmp_, "v"));
    double* radius = static_cast<double*>(lammps_extract_atom(lmp_, "radius"));
    std::vector<double> mine(8 * static_cast<size_t>(nl));
    for (int i = 0; i < nl; ++i) {
      double* m = &mine[8 * static_cast<size_t>(i)];
      m[0] = tag[i], m[1] = x[i][0], m[2] = x[i][1], m[3] = x[i][2];
      m[4] = v[i][0], m[5] = v[i][1], m[6] = v[i][2], m[7] = radius[i];
    }
    std::vector<double> all = gather(mine);
    std::vector<Particle> out(order_.size());
    std::vector<bool> seen(order_.size(), false);
    for (size_t k = 0; k + 7 < all.size(); k += 8) {
      auto it = index_of_.find(static_cast<int>(all[k]));
      if (it == index_of_.end()) continue;
      Particle& p = out[it->second];
      p.position = {all[k + 1], all[k + 2], all[k + 3]};
      p.velocity = {all[k + 4], all[k + 5], all[k + 6]};
      p.radius = all[k + 7];
      p.mass = particle_mass(params_, p.radius);
      seen[it->second] = true;
    }
    for (size_t i = 0; i < out.size(); ++i) {
      out[i].id = ids_[i];
      if (!seen[i]) {  // lost by LAMMPS (left its box): flagged, to be removed
        lost_.insert(order_[i]);
        out[i].position = box_.centre();
        out[i].radius = params_.radius;
        out[i].mass = 1;
      }
    }
    return out;
  }

  std::vector<size_t> sort_by_cells() override {
    // LAMMPS keeps its own atoms in spatial order (atom_modify sort); the
    // engine's indices are its own and stay.
    std::vector<size_t> order(order_.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    return order;
  }

  std::vector<size_t> flagged_particles() override {
    flush();
    if (static_cast<double>(order_.size()) != lammps_get_natoms(lmp_)) find_lost();
    std::vector<double> mine(flagged_tags_.begin(), flagged_tags_.end());
    std::vector<double> all = gather(mine);
    for (int t : lost_) all.push_back(t);  // the same on every rank
    std::vector<size_t> out;
    for (double t : all) {
      auto it = index_of_.find(static_cast<int>(t));
      if (it != index_of_.end()) out.push_back(it->second);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

  void clear_flags() override { flagged_tags_.clear(); }
  size_t size() const override { return order_.size(); }
  uint64_t steps_done() const override { return steps_ + pending_; }

  /// The callback of `fix external pf/callback` (post_force: the pair
  /// forces of this step are in atom->f): pfill's integration and wall on
  /// this rank's atoms.
  void on_step(int64_t step, int nlocal, int* tags, double** x, double** fext) {
    for (int i = 0; i < nlocal; ++i) fext[i][0] = fext[i][1] = fext[i][2] = 0;
    // `run` calls the fixes' setup too (post_force at the run's first
    // step number): that is no step.
    if (step <= static_cast<int64_t>(run_start_)) return;
    const EngineConstants& c = constants_;
    double** f = static_cast<double**>(lammps_extract_atom(lmp_, "f"));
    double** v = static_cast<double**>(lammps_extract_atom(lmp_, "v"));
    double* radius = static_cast<double*>(lammps_extract_atom(lmp_, "radius"));
    double* rmass = static_cast<double*>(lammps_extract_atom(lmp_, "rmass"));
    double** omega = static_cast<double**>(lammps_extract_atom(lmp_, "omega"));
    LocalRecord rec;
    rec.particles = nlocal;
    rec.colliding_pairs = contacts(nlocal, x, v, radius, rmass);
    const ScalarGrid* field = field_;
    for (int i = 0; i < nlocal; ++i) {
      double u[3] = {v[i][0], v[i][1], v[i][2]};
      double p[3] = {x[i][0], x[i][1], x[i][2]};
      const double p0[3] = {p[0], p[1], p[2]};
      const double* fd = &dashpot_[3 * static_cast<size_t>(i)];
      lammps_physics::pf_kick_drift(&u[0], &u[1], &u[2], &p[0], &p[1], &p[2], f[i][0] + fd[0], f[i][1] + fd[1],
                                    f[i][2] + fd[2],
                                    1 / rmass[i], c.dt, c.damping_factor, c.max_speed);
      // omega[i][0] (rotation is not integrated) keeps a bound on the
      // field's value at the atom: its last sample plus the field's slope
      // times the moves since. While that bound says the sphere cannot reach
      // the wall, the field is not read (at N = 16,000 on 1 rank, reading it
      // for every atom was half of a step: cache misses in a 57 MiB grid);
      // the result is the same, as the push and the flag need phi > -r.
      const double moved_bound = omega[i][0] + lipschitz_ * std::sqrt((p[0] - p0[0]) * (p[0] - p0[0]) +
                                                                     (p[1] - p0[1]) * (p[1] - p0[1]) +
                                                                     (p[2] - p0[2]) * (p[2] - p0[2]));
      if (field && moved_bound < -radius[i]) {
        omega[i][0] = moved_bound;
      } else if (field) {
        double g[3];
        const double phi = sample(*field, p[0], p[1], p[2], g);
        const double gx = (p[0] - field->origin.x) / field->spacing, gy = (p[1] - field->origin.y) / field->spacing,
                     gz = (p[2] - field->origin.z) / field->spacing;
        const bool outside_box = gx < 0 || gy < 0 || gz < 0 || gx > field->dims[0] - 1 ||
                                 gy > field->dims[1] - 1 || gz > field->dims[2] - 1;
        if (phi > 0 || outside_box) {
          ++rec.flagged;
          flagged_tags_.insert(tags[i]);
        }
        const double after = wall_push(&p[0], &p[1], &p[2], &u[0], &u[1], &u[2], phi, g, phi > -radius[i],
                                       radius[i], params_.wall_restitution, *field);
        omega[i][0] = after;
      }
      // Never past the box (LAMMPS would lose the atom): the wall brings it back.
      for (int a = 0; a < 3; ++a) p[a] = std::min(std::max(p[a], lo_[a]), hi_[a]);
      x[i][0] = p[0], x[i][1] = p[1], x[i][2] = p[2];
      v[i][0] = u[0], v[i][1] = u[1], v[i][2] = u[2];
      rec.kinetic_energy += 0.5 * rmass[i] * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
      rec.max_speed = std::max(rec.max_speed, std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]));
      const double d[3] = {p[0] - p0[0], p[1] - p0[1], p[2] - p0[2]};
      rec.max_displacement = std::max(rec.max_displacement, std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
    }
    local_history_.push_back(rec);
  }

 private:
  void check_supported() const {
    const double a = params_.exponent_a, b = params_.exponent_b;
    if (!(a == 12 && b == 6) && !(a > b && b > 0))
      throw Error("lammps engine: exponents must satisfy a > b > 0");
    if (params_.force_cap > 0)
      throw Error("lammps engine: a pair force cap (force_cap) is not available on LAMMPS; leave it 0");
  }

  void command(const std::string& c) { lammps_command(lmp_, c.c_str()); }

  int nlocal() const { return *static_cast<int*>(lammps_extract_global(lmp_, "nlocal")); }

  /// Forget this rank's ghost atoms before atoms are created through the
  /// library. LAMMPS stores ghosts after the owned atoms (indices nlocal to
  /// nlocal + nghost - 1), and `lammps_create_atoms` (LAMMPS 29 Sep 2021)
  /// writes each new atom at index nlocal without dropping the ghosts first,
  /// as the create_atoms command (and delete_atoms, and the exchange) do: the
  /// new atoms overwrite ghosts, nlocal + nghost then reaches one slot past
  /// the last one written for each new atom, and its map_set (and the next
  /// exchange's map_clear) hash the tags found in those never written slots
  /// (uninitialised memory from the arrays' realloc: negative tags index the hash's buckets out of
  /// bounds, heap corruption at 2 ranks and more; one rank with `boundary f f f`
  /// has no ghosts). The ghosts are rebuilt by the next `run pre yes` (a
  /// birth marks the state dirty); lammps_create_atoms itself rebuilds the
  /// atom map (map_init, map_set) from the owned atoms.
  void drop_ghosts() {
    if (!box_made_) return;
    *static_cast<int*>(lammps_extract_global(lmp_, "nghost")) = 0;
  }

  /// The box LAMMPS decomposes: the field's box (or the given one) and a margin.
  void make_box(const Box3& inner) {
    const EngineConstants& c = constants_;
    const Vec3 s = inner.size();
    const double margin = 2 * c.list_reach + 1e-3 * std::max({s.x, s.y, s.z});
    const Vec3 lo = inner.lo - Vec3{margin, margin, margin}, hi = inner.hi + Vec3{margin, margin, margin};
    box_ = Box3{lo, hi};
    // Atoms are clamped a little inside the box (LAMMPS drops atoms on or past a fixed boundary).
    const double in = 0.25 * margin;
    lo_[0] = lo.x + in, lo_[1] = lo.y + in, lo_[2] = lo.z + in;
    hi_[0] = hi.x - in, hi_[1] = hi.y - in, hi_[2] = hi.z - in;
    const double rc = c.cutoff;
    const double a = params_.exponent_a, b = params_.exponent_b;
    std::ostringstream cmd;
    cmd.precision(17);
    cmd << "units lj\natom_style sphere\natom_modify map hash\nboundary f f f\ncomm_modify vel yes\n"
        << "newton off\n"
        << "region pf_box block " << lo.x << " " << hi.x << " " << lo.y << " " << hi.y << " " << lo.z << " " << hi.z
        << "\ncreate_box 1 pf_box\n";
    // The potential: 4 eps [(sigma/d)^a - (sigma/d)^b], cut at rc (the
    // minimum for the purely repulsive default), shifted to 0 there.
    std::string pair, coeff;
    if (a == 12 && b == 6) {
      pair = "lj/cut " + num(rc);
      coeff = "lj/cut " + num(params_.eps) + " " + num(c.sigma) + " " + num(rc);
      pair_line_ = "lj/cut";
    } else {
      if (!lammps_has_style(lmp_, "pair", "mie/cut"))
        throw Error("lammps engine: exponents other than 12,6 need LAMMPS' mie/cut pair style, which this LAMMPS lacks");
      // mie/cut: C eps' [(s/d)^a - (s/d)^b], C = a/(a-b) (a/b)^(b/(a-b)); pfill's prefactor is 4 eps.
      const double cm = a / (a - b) * std::pow(a / b, b / (a - b));
      pair = "mie/cut " + num(rc);
      coeff = "mie/cut " + num(4 * params_.eps / cm) + " " + num(c.sigma) + " " + num(a) + " " + num(b) + " " + num(rc);
      pair_line_ = "mie/cut";
    }
    // The contact dashpot is pfill's own (the callback, over this pair
    // style's list): with `newton off` a pair across ranks is listed on
    // both, so each rank can apply it to its own atom without a reverse
    // communication.
    cmd << "pair_style " << pair << "\npair_coeff * * " << coeff.substr(coeff.find(' ') + 1) << "\n";
    pair_line_ += " + pfill's contact dashpot in the callback";
    cmd << "pair_modify shift yes\n";
    const double skin = (params_.skin_sigma > 0 ? params_.skin_sigma : kCpuFormSkinSigma) * c.sigma;
    cmd << "neighbor " << num(skin) << " bin\nneigh_modify delay 0 every 1 check yes\n"
        << "fix pf_step all external pf/callback 1 1\n"
        << "timestep " << num(c.dt) << "\n"
        << "thermo_style custom step\nthermo 0\nthermo_modify lost ignore norm no\n";
    pair_line_ += ", skin " + num(skin / c.sigma) + " sigma";
    lammps_commands_string(lmp_, cmd.str().c_str());
    lammps_set_fix_external_callback(
        lmp_, "pf_step",
        [](void* self, int64_t step, int n, int* ids, double** x, double** f) {
          static_cast<LammpsEngine*>(self)->on_step(step, n, ids, x, f);
        },
        this);
    box_made_ = true;
  }

  void field_changed() {
    const ScalarGrid& f = *field_;
    // The trilinear interpolant's slope is at most the norm of the largest
    // sample differences along x, y, z over the spacing.
    double dmax[3] = {0, 0, 0};
    for (int k = 0; k < f.dims[2]; ++k)
      for (int j = 0; j < f.dims[1]; ++j)
        for (int i = 0; i < f.dims[0]; ++i) {
          const double v = f.at(i, j, k);
          if (i + 1 < f.dims[0]) dmax[0] = std::max(dmax[0], std::fabs(f.at(i + 1, j, k) - v));
          if (j + 1 < f.dims[1]) dmax[1] = std::max(dmax[1], std::fabs(f.at(i, j + 1, k) - v));
          if (k + 1 < f.dims[2]) dmax[2] = std::max(dmax[2], std::fabs(f.at(i, j, k + 1) - v));
        }
    lipschitz_ = 1.0001 * std::sqrt(dmax[0] * dmax[0] + dmax[1] * dmax[1] + dmax[2] * dmax[2]) / f.spacing;
    // Bounds kept from another field mean nothing: every atom samples the new one first.
    if (box_made_ && nlocal() > 0) {
      double** omega = static_cast<double**>(lammps_extract_atom(lmp_, "omega"));
      for (int i = 0; i < nlocal(); ++i) omega[i][0] = 0;
    }
    if (!box_made_) {
      const Vec3 hi = f.origin + Vec3{(f.dims[0] - 1) * f.spacing, (f.dims[1] - 1) * f.spacing,
                                      (f.dims[2] - 1) * f.spacing};
      make_box(Box3{f.origin, hi});
    }
  }

  void flush() {
    if (pending_ == 0) return;
    if (!box_made_) make_box(Box3{{-1, -1, -1}, {1, 1, 1}});
    // Ranks' shares of the atoms even again as the fill grows (each 10% more atoms).
    if (dirty_ && ranks_ > 1 && static_cast<double>(order_.size()) > 1.1 * balanced_at_ + 100) {
      command("balance 1.05 shift xyz 10 1.02");
      balanced_at_ = static_cast<double>(order_.size());
    }
    run_start_ = steps_;
    // `pre no` skips the set-up (re-neighbouring, ghost exchange) when
    // nothing but the steps changed the atoms since the last run.
    command("run " + std::to_string(pending_) + " pre " + (dirty_ ? "yes" : "no") + " post no");
    steps_ += pending_;
    pending_ = 0;
    dirty_ = false;
  }

  /// Over this rank's pair list (the pair style's, `newton off`: a pair
  /// with a ghost is listed on both its ranks): the contact dashpot of
  /// physics.cl on this rank's atoms into dashpot_, and the pairs whose
  /// spheres overlap (d < r_i + r_j; a pair with a ghost counts half, so
  /// the sum over ranks counts it once). Positions and velocities are the
  /// step's start (ghosts' from this step's communication).
  double contacts(int nlocal, double** x, double** v, const double* radius, const double* rmass) {
    dashpot_.assign(3 * static_cast<size_t>(nlocal), 0.0);
    const int list = lammps_find_pair_neighlist(lmp_, pair_name(), 1, 0, 0);
    if (list < 0) return 0;
    const EngineConstants& c = constants_;
    const double contact2 = c.contact_distance * c.contact_distance;
    const bool damp = c.dashpot > 0;
    const int n = lammps_neighlist_num_elements(lmp_, list);
    double count = 0;
    for (int e = 0; e < n; ++e) {
      int i = 0, nn = 0;
      int* neigh = nullptr;
      lammps_neighlist_element_neighbors(lmp_, list, e, &i, &nn, &neigh);
      if (i >= nlocal) continue;
      const double* xi = x[i];
      for (int k = 0; k < nn; ++k) {
        const int j = neigh[k] & 0x3FFFFFFF;  // NEIGHMASK: special-bond bits off
        const double dx = xi[0] - x[j][0], dy = xi[1] - x[j][1], dz = xi[2] - x[j][2];
        const double d2 = dx * dx + dy * dy + dz * dz;
        const double rs = radius[i] + radius[j];
        if (d2 >= std::max(rs * rs, contact2)) continue;
        const bool mine = j < nlocal;
        if (d2 < rs * rs) count += mine ? 1 : 0.5;
        if (!damp || !(d2 > 0)) continue;
        const double inv_d = 1 / std::sqrt(d2);
        const double nx = dx * inv_d, ny = dy * inv_d, nz = dz * inv_d;
        const double un = (v[i][0] - v[j][0]) * nx + (v[i][1] - v[j][1]) * ny + (v[i][2] - v[j][2]) * nz;
        const double cd = lammps_physics::pf_contact_damping(un, 1 / rmass[i], 1 / rmass[j], c.dashpot, 1.0);  // equal radii: the pair scale is 1 (unequal radii on LAMMPS: not yet)
        double* fi = &dashpot_[3 * static_cast<size_t>(i)];
        fi[0] += cd * nx, fi[1] += cd * ny, fi[2] += cd * nz;
        if (mine) {
          double* fj = &dashpot_[3 * static_cast<size_t>(j)];
          fj[0] -= cd * nx, fj[1] -= cd * ny, fj[2] -= cd * nz;
        }
      }
    }
    return count;
  }

  bool inside_box(const Vec3& p) const {
    return p.x >= lo_[0] && p.y >= lo_[1] && p.z >= lo_[2] && p.x <= hi_[0] && p.y <= hi_[1] && p.z <= hi_[2];
  }

  const char* pair_name() const { return pair_line_.rfind("mie/cut", 0) == 0 ? "mie/cut" : "lj/cut"; }

  /// Every rank's `mine`, in rank order, on every rank.
  std::vector<double> gather(const std::vector<double>& mine) {
    if (ranks_ == 1) return mine;
    int n = static_cast<int>(mine.size());
    std::vector<int> counts(static_cast<size_t>(ranks_)), offsets(static_cast<size_t>(ranks_), 0);
    MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_);
    for (int r = 1; r < ranks_; ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
    std::vector<double> all(static_cast<size_t>(offsets.back() + counts.back()));
    MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE, comm_);
    return all;
  }

  /// Atoms LAMMPS dropped (past its box): the engine's tags it no longer has.
  void find_lost() {
    const int nl = nlocal();
    int* tag = static_cast<int*>(lammps_extract_atom(lmp_, "id"));
    std::vector<double> mine(tag, tag + nl);
    std::vector<double> all = gather(mine);
    std::unordered_map<int, bool> present;
    for (double t : all) present[static_cast<int>(t)] = true;
    for (int t : order_)
      if (!present.count(t)) lost_.insert(t);
  }

  EngineParams params_;
  EngineConstants constants_;
  void* lmp_ = nullptr;
  MPI_Comm comm_;
  int rank_ = 0, ranks_ = 1;
  bool box_made_ = false;
  Box3 box_;
  double lo_[3] = {0, 0, 0}, hi_[3] = {0, 0, 0};
  std::string pair_line_;
  ScalarGrid own_field_;
  const ScalarGrid* field_ = nullptr;
  // The engine's indices (the same on every rank): index -> LAMMPS tag, the caller's id, tag -> index.
  std::vector<int> order_;
  std::vector<uint64_t> ids_;
  std::unordered_map<int, size_t> index_of_;
  int next_tag_ = 1;
  uint64_t steps_ = 0, run_start_ = 0, history_first_ = 0;
  size_t pending_ = 0;
  bool dirty_ = true;
  double balanced_at_ = 0;  // the atom count at the last `balance`
  double lipschitz_ = 2;    // the field interpolant's largest slope
  std::vector<LocalRecord> local_history_;
  std::vector<double> dashpot_;  // the contact dashpot's force on each of this rank's atoms, this step
  std::unordered_set<int> flagged_tags_;  // this rank's atoms flagged outside since clear_flags
  std::unordered_set<int> lost_;          // tags LAMMPS dropped (the same on every rank)
};

}  // namespace

bool lammps_available() { return true; }

MpiWorld lammps_mpi_start() {
  ensure_mpi();
  MpiWorld w;
  MPI_Comm_rank(MPI_COMM_WORLD, &w.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &w.size);
  return w;
}

void lammps_mpi_abort(int code) {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  if (!initialized || finalized) return;
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size > 1) MPI_Abort(MPI_COMM_WORLD, code);
}

std::unique_ptr<ParticleEngine> make_lammps_engine(const EngineParams& params) {
  return std::make_unique<LammpsEngine>(params);
}

std::function<std::unique_ptr<ParticleEngine>(const EngineParams&)> lammps_engine_factory() {
  return [](const EngineParams& p) { return make_lammps_engine(p); };
}

}  // namespace pfill
#endif
