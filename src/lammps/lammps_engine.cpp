// The LAMMPS engine (docs/lammps_engine.md): a ParticleEngine whose
// particles live in a LAMMPS instance on MPI_COMM_WORLD. LAMMPS owns the
// domain decomposition, the neighbour lists, the halo exchange, the
// migration of atoms between ranks and the potential's pair forces (lj/cut,
// or mie/cut, cut at the potential's minimum for the repulsive default);
// pfill's own step rules run in a `fix external pf/callback` on each rank's
// own atoms (step_callback.hpp). This file ties together the LAMMPS
// instance (lammps_session.hpp), the engine's indices (particle_book.hpp)
// and that callback: the box and the settings handed to LAMMPS, births,
// removals, runs, reads.
//
// SPMD: every rank makes the same calls with the same arguments (the fill's
// host loop runs on every rank), so the engine's bookkeeping of indices and
// ids is the same everywhere; a wave's births are booked on every rank but
// each rank creates only those it decided, in its sub-domain
// (add_decided_particles); reads and records are reductions. The births'
// room test sees only this rank's atoms and a halo (birth_view).
#ifdef PFILL_WITH_LAMMPS
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "lammps/birth_halo.hpp"
#include "lammps/birth_tally.hpp"
#include "lammps/lammps_session.hpp"
#include "lammps/new_atoms.hpp"
#include "lammps/particle_book.hpp"
#include "lammps/step_callback.hpp"
#include "pfill/error.hpp"
#include "pfill/lammps.hpp"

namespace pfill {
namespace {

using lammps_engine::LammpsSession;
using lammps_engine::LocalRecord;
using lammps_engine::num;
using lammps_engine::ParticleBook;
using lammps_engine::StepCallback;

/// The engine's constants; then refuses, in one line and before LAMMPS is
/// started, what LAMMPS cannot run as pfill's engine does.
EngineConstants checked_constants(const EngineParams& params) {
  EngineConstants constants = derive_constants(params);
  const double a = params.exponent_a, b = params.exponent_b;
  if (!(a == 12 && b == 6) && !(a > b && b > 0)) throw Error("lammps engine: exponents must satisfy a > b > 0");
  if (params.force_cap > 0)
    throw Error("lammps engine: a pair force cap (force_cap) is not available on LAMMPS; leave it 0");
  if (params.fire.on)
    throw Error("lammps engine: FIRE (fire.on) runs on the OpenCL engine only; the finish relaxes by damping here");
  return constants;
}

class LammpsEngine final : public ParticleEngine {
 public:
  explicit LammpsEngine(const EngineParams& params)
      : params_(params),
        constants_(checked_constants(params)),
        lmp_(std::make_unique<LammpsSession>()),
        step_(params_, constants_, *lmp_) {
    if (!params_.domain.empty()) make_box(params_.domain);
  }

  LammpsEngine(const LammpsEngine&) = delete;
  LammpsEngine& operator=(const LammpsEngine&) = delete;

  const EngineParams& params() const override { return params_; }
  const EngineConstants& constants() const override { return constants_; }
  std::string describe() const override {
    const int ranks = lmp_->ranks();
    return "the LAMMPS engine (LAMMPS " + std::to_string(lmp_->version()) + ", " + std::to_string(ranks) +
           " MPI rank" + (ranks == 1 ? "" : "s") + "): " + pair_line_;
  }

  void set_field(const ScalarGrid& field) override {
    own_field_ = field;
    // EngineParams::wall_offset: added to each sample as a float, as the kernels read it
    for (float& v : own_field_.values) v += static_cast<float>(params_.wall_offset);
    field_changed(own_field_);
  }

  void share_field(const ScalarGrid& field) override {
    if (params_.wall_offset != 0) return set_field(field);
    field_changed(field);
  }

  size_t add_particles(const std::vector<Particle>& ps) override {
    flush();
    const size_t first = book_.size();
    if (ps.empty()) return first;
    // Refused here, on every rank alike (each is given every particle),
    // before LAMMPS sees them (its box from the particles, or create_atoms,
    // would stop the program).
    for (const Particle& p : ps)
      if (!finite(p)) throw Error(particle_error(p));
    if (!box_made_) {
      Box3 b;
      for (const Particle& p : ps) b.add(p.position);
      make_box(b);
    }
    for (const Particle& p : ps) {
      const std::string e = particle_error(p);
      if (!e.empty()) throw Error(e);
    }
    const std::vector<int> tags = book_.new_tags(ps.size());
    lammps_engine::NewAtoms atoms;
    for (size_t k = 0; k < ps.size(); ++k) atoms.add(tags[k], ps[k], mass_of(ps[k]));
    create(atoms, ps.size());  // each rank keeps those in its sub-domain
    for (size_t k = 0; k < ps.size(); ++k) book_.append(tags[k], ps[k].id);
    dirty_ = true;
    return first;
  }

  /// Each rank passes lammps_create_atoms only the births it decided (its
  /// sub-domain's); every rank books every member's tag and id, in the
  /// order of `ids`, so the indices stay the same everywhere.
  size_t add_decided_particles(const std::vector<Particle>& mine, const std::vector<uint64_t>& ids) override {
    flush();
    const size_t first = book_.size();
    if (ids.empty()) return first;
    std::unordered_map<uint64_t, size_t> slot;  // id -> its place in the batch
    for (size_t k = 0; k < ids.size(); ++k) slot.emplace(ids[k], k);
    if (!box_made_) make_box(bounds_over_ranks(mine));
    // Each rank checks its own; an error any rank meets ends every rank alike.
    std::string error;
    for (const Particle& p : mine) {
      if (error.empty()) error = particle_error(p);
      if (error.empty() && !slot.count(p.id))
        error = "lammps engine: a birth's id " + std::to_string(p.id) + " is not one of its batch's";
    }
    lmp_->throw_if_any(error);
    const std::vector<int> tags = book_.new_tags(ids.size());
    lammps_engine::NewAtoms atoms;
    for (const Particle& p : mine) atoms.add(tags[slot[p.id]], p, mass_of(p));
    atoms.sort_by_tag();
    lammps_engine::BirthTally& tally = lammps_engine::birth_tally();
    tally.outside += lammps_engine::share_strays(*lmp_, atoms);
    tally.batches += 1, tally.newborns += ids.size(), tally.passed += atoms.size();
    create(atoms, ids.size());
    for (size_t k = 0; k < ids.size(); ++k) book_.append(tags[k], ids[k]);
    dirty_ = true;
    return first;
  }

  void remove_particles(std::vector<size_t> indices) override {
    flush();
    const std::vector<int> gone = book_.remove(std::move(indices));
    if (gone.empty()) return;
    lmp_->delete_atoms(gone);
    for (int t : gone) step_.flagged_tags().erase(t), book_.lost().erase(t);
    dirty_ = true;
  }

  void run_steps(size_t k) override { pending_ += k; }

  std::vector<StepRecord> read_history() override {
    flush();
    const std::vector<LocalRecord> local = step_.take_history();
    const size_t n = local.size();
    std::vector<double> sums(4 * n), maxes(2 * n);
    for (size_t s = 0; s < n; ++s) {
      const LocalRecord& r = local[s];
      sums[4 * s] = r.kinetic_energy, sums[4 * s + 1] = r.colliding_pairs, sums[4 * s + 2] = r.flagged,
               sums[4 * s + 3] = r.particles;
      maxes[2 * s] = r.max_speed, maxes[2 * s + 1] = r.max_displacement;
    }
    if (lmp_->ranks() > 1 && n > 0) {
      MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_DOUBLE, MPI_SUM, lmp_->comm());
      MPI_Allreduce(MPI_IN_PLACE, maxes.data(), static_cast<int>(maxes.size()), MPI_DOUBLE, MPI_MAX, lmp_->comm());
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
    return out;
  }

  std::vector<Particle> read_particles() override {
    flush();
    // Each rank's own atoms: tag, x, v, radius, mass (8 doubles each), gathered on every rank.
    const int nl = lmp_->nlocal();
    int* tag = lmp_->atoms<int*>("id");
    double** x = lmp_->atoms<double**>("x");
    double** v = lmp_->atoms<double**>("v");
    double* radius = lmp_->atoms<double*>("radius");
    std::vector<double> mine(8 * static_cast<size_t>(nl));
    for (int i = 0; i < nl; ++i) {
      double* m = &mine[8 * static_cast<size_t>(i)];
      m[0] = tag[i], m[1] = x[i][0], m[2] = x[i][1], m[3] = x[i][2];
      m[4] = v[i][0], m[5] = v[i][1], m[6] = v[i][2], m[7] = radius[i];
    }
    std::vector<double> all = lmp_->gather(mine);
    std::vector<Particle> out(book_.size());
    std::vector<bool> seen(book_.size(), false);
    for (size_t k = 0; k + 7 < all.size(); k += 8) {
      const size_t index = book_.index_of(static_cast<int>(all[k]));
      if (index == book_.size()) continue;
      Particle& p = out[index];
      p.position = {all[k + 1], all[k + 2], all[k + 3]};
      p.velocity = {all[k + 4], all[k + 5], all[k + 6]};
      p.radius = all[k + 7];
      p.mass = particle_mass(params_, p.radius);
      seen[index] = true;
    }
    for (size_t i = 0; i < out.size(); ++i) {
      out[i].id = book_.id(i);
      if (!seen[i]) {  // lost by LAMMPS (left its box): flagged, to be removed
        book_.lost().insert(book_.tag(i));
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
    std::vector<size_t> order(book_.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    return order;
  }

  std::vector<size_t> flagged_particles() override {
    flush();
    if (static_cast<double>(book_.size()) != lmp_->natoms()) find_lost();
    const std::unordered_set<int>& flagged = step_.flagged_tags();
    std::vector<double> mine(flagged.begin(), flagged.end());
    std::vector<double> all = lmp_->gather(mine);
    for (int t : book_.lost()) all.push_back(t);  // the same on every rank
    std::vector<size_t> out;
    for (double t : all) {
      const size_t index = book_.index_of(static_cast<int>(t));
      if (index != book_.size()) out.push_back(index);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

  void clear_flags() override { step_.flagged_tags().clear(); }

  /// At P > 1: this rank's atoms and the others' within `reach` of its
  /// sub-domain, whose sites it decides (birth_halo.hpp); no gather.
  BirthView birth_view(double reach, bool complete) override {
    flush();
    if (complete || lmp_->ranks() == 1) return ParticleEngine::birth_view(reach, complete);
    return lammps_engine::birth_halo(*lmp_, reach);
  }

  void sum_over_processes(std::vector<int>& counts) override {
    if (lmp_->ranks() > 1 && !counts.empty())
      MPI_Allreduce(MPI_IN_PLACE, counts.data(), static_cast<int>(counts.size()), MPI_INT, MPI_SUM, lmp_->comm());
  }
  size_t size() const override { return book_.size(); }
  uint64_t steps_done() const override { return steps_ + pending_; }

 private:
  /// The box LAMMPS decomposes: the field's box (or the given one) and a
  /// margin; then the potential, the lists and the callback's fix.
  void make_box(const Box3& inner) {
    const EngineConstants& c = constants_;
    const double in_lo[3] = {inner.lo.x, inner.lo.y, inner.lo.z}, in_hi[3] = {inner.hi.x, inner.hi.y, inner.hi.z};
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(in_lo[a]) || !std::isfinite(in_hi[a]) || in_lo[a] > in_hi[a])
        throw Error("lammps engine: the domain " + num(in_lo[0]) + "," + num(in_lo[1]) + "," + num(in_lo[2]) +
                    " to " + num(in_hi[0]) + "," + num(in_hi[1]) + "," + num(in_hi[2]) +
                    " is not a box (finite, lo <= hi on each axis)");
    const Vec3 s = inner.size();
    const double margin = 2 * c.list_reach + 1e-3 * std::max({s.x, s.y, s.z});
    const Vec3 lo = inner.lo - Vec3{margin, margin, margin}, hi = inner.hi + Vec3{margin, margin, margin};
    box_ = Box3{lo, hi};
    // Atoms are clamped a little inside the box (LAMMPS drops atoms on or past a fixed boundary).
    const double in = 0.25 * margin;
    lo_[0] = lo.x + in, lo_[1] = lo.y + in, lo_[2] = lo.z + in;
    hi_[0] = hi.x - in, hi_[1] = hi.y - in, hi_[2] = hi.z - in;
    step_.set_clamp(lo_, hi_);
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
    std::string pair, coeff, style;
    if (a == 12 && b == 6) {
      pair = "lj/cut " + num(rc);
      coeff = "lj/cut " + num(params_.eps) + " " + num(c.sigma) + " " + num(rc);
      style = "lj/cut";
    } else {
      if (!lammps_has_style(lmp_->handle(), "pair", "mie/cut"))
        throw Error("lammps engine: exponents other than 12,6 need LAMMPS' mie/cut pair style, which this LAMMPS lacks");
      // mie/cut: C eps' [(s/d)^a - (s/d)^b], C = a/(a-b) (a/b)^(b/(a-b)); pfill's prefactor is 4 eps.
      const double cm = a / (a - b) * std::pow(a / b, b / (a - b));
      pair = "mie/cut " + num(rc);
      coeff = "mie/cut " + num(4 * params_.eps / cm) + " " + num(c.sigma) + " " + num(a) + " " + num(b) + " " + num(rc);
      style = "mie/cut";
    }
    step_.set_pair_style(style);
    pair_line_ = style;
    // The contact dashpot is pfill's own (the callback, over this pair
    // style's list): with `newton off` a pair across ranks is listed on
    // both, so each rank can apply it to its own atom without a reverse
    // communication.
    cmd << "pair_style " << pair << "\npair_coeff * * " << coeff.substr(coeff.find(' ') + 1) << "\n";
    pair_line_ += " + pfill's contact dashpot in the callback";
    cmd << "pair_modify shift yes\n";
    const double skin = (params_.skin_sigma > 0 ? params_.skin_sigma : kCpuFormSkinSigma) * c.sigma;
    refuse_too_many_bins(hi - lo, rc + skin);
    cmd << "neighbor " << num(skin) << " bin\nneigh_modify delay 0 every 1 check yes\n"
        << "fix pf_step all external pf/callback 1 1\n"
        << "timestep " << num(c.dt) << "\n"
        << "thermo_style custom step\nthermo 0\nthermo_modify lost ignore norm no\n";
    pair_line_ += ", skin " + num(skin / c.sigma) + " sigma";
    lmp_->commands(cmd.str());
    step_.install("pf_step");
    box_made_ = true;
  }

  /// LAMMPS bins each rank's sub-domain (and its ghost shell) for the
  /// lists at half the list's reach, and stops the program past 2^31 - 1
  /// bins on a rank ("Too many neighbor bins", unseen under -screen none).
  /// The sub-domains tile the box, so some rank has at least the box's
  /// bins over P: past the limit, that rank would stop. Refused here in one
  /// line instead (a box far larger than the spheres: about 3e8 spheres in
  /// a mesh's box at P = 1).
  void refuse_too_many_bins(const Vec3& size, double reach) const {
    const double bin = 0.5 * reach;
    const double bins = std::floor(size.x / bin) * std::floor(size.y / bin) * std::floor(size.z / bin);
    const double per_rank = bins / lmp_->ranks();
    if (per_rank > 2147483647.0) {
      char b[64];
      std::snprintf(b, sizeof b, "%.3g", per_rank);
      throw Error("lammps engine: the box would need " + std::string(b) +
                  " neighbour-list bins a rank, past LAMMPS' limit of 2^31 - 1; use more MPI ranks, or larger "
                  "spheres (fewer of them) for this mesh");
    }
  }

  void field_changed(const ScalarGrid& f) {
    step_.set_field(&f, box_made_);
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
    if (dirty_ && lmp_->ranks() > 1 && static_cast<double>(book_.size()) > 1.1 * balanced_at_ + 100) {
      lmp_->command("balance 1.05 shift xyz 10 1.02");
      balanced_at_ = static_cast<double>(book_.size());
    }
    // `pre no` skips the set-up (re-neighbouring, ghost exchange) when
    // nothing but the steps changed the atoms since the last run. LAMMPS
    // stops the program at `run N` past N = 2^31 - 1: longer waits run in pieces.
    while (pending_ > 0) {
      const size_t k = std::min<size_t>(pending_, 2147483647);
      step_.set_run_start(steps_);
      lmp_->command("run " + std::to_string(k) + " pre " + (dirty_ ? "yes" : "no") + " post no");
      steps_ += k;
      pending_ -= k;
      dirty_ = false;
    }
    lammps_engine::last_subdomain() = lmp_->subdomain();
  }

  static bool finite(const Particle& p) { return is_finite(p.position) && is_finite(p.velocity); }

  /// What LAMMPS could not take of p, in one line; empty where it can.
  std::string particle_error(const Particle& p) const {
    if (!finite(p)) return "lammps engine: a particle's position or velocity is not a finite number";
    if (!(p.radius > 0) || p.radius > constants_.max_radius * (1 + 1e-9))
      return "lammps engine: a particle's radius " + num(p.radius) + " is not in (0, max_radius]";
    if (box_made_ && !inside_box(p.position))
      return "lammps engine: a particle at " + num(p.position.x) + "," + num(p.position.y) + "," +
             num(p.position.z) + " lies outside the engine's box";
    return "";
  }

  double mass_of(const Particle& p) const { return p.mass > 0 ? p.mass : particle_mass(params_, p.radius); }

  /// The box of every rank's particles (a birth batch before any box: no field set).
  Box3 bounds_over_ranks(const std::vector<Particle>& ps) const {
    std::string error;
    for (const Particle& p : ps)
      if (error.empty() && !finite(p)) error = particle_error(p);
    lmp_->throw_if_any(error);
    Box3 b;
    for (const Particle& p : ps) b.add(p.position);
    double lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
    MPI_Allreduce(MPI_IN_PLACE, lo, 3, MPI_DOUBLE, MPI_MIN, lmp_->comm());
    MPI_Allreduce(MPI_IN_PLACE, hi, 3, MPI_DOUBLE, MPI_MAX, lmp_->comm());
    return Box3{{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
  }

  /// Creates the atoms (collective); `n`: how many the ranks meant to create.
  void create(const lammps_engine::NewAtoms& atoms, size_t n) {
    const int made = lammps_engine::create_new_atoms(*lmp_, atoms);
    if (made != static_cast<int>(n))
      throw Error("lammps engine: " + std::to_string(n) + " particles given, " + std::to_string(made) + " created");
  }

  bool inside_box(const Vec3& p) const {
    return p.x >= lo_[0] && p.y >= lo_[1] && p.z >= lo_[2] && p.x <= hi_[0] && p.y <= hi_[1] && p.z <= hi_[2];
  }

  /// Atoms LAMMPS dropped (past its box): the engine's tags it no longer has.
  void find_lost() {
    const int nl = lmp_->nlocal();
    int* tag = lmp_->atoms<int*>("id");
    std::vector<double> mine(tag, tag + nl);
    std::vector<double> all = lmp_->gather(mine);
    std::unordered_map<int, bool> present;
    for (double t : all) present[static_cast<int>(t)] = true;
    for (int t : book_.tags())
      if (!present.count(t)) book_.lost().insert(t);
  }

  EngineParams params_;
  EngineConstants constants_;
  std::unique_ptr<LammpsSession> lmp_;
  StepCallback step_;  // after lmp_: it holds a reference to it
  ParticleBook book_;  // the engine's indices, the same on every rank
  bool box_made_ = false;
  Box3 box_;
  double lo_[3] = {0, 0, 0}, hi_[3] = {0, 0, 0};
  std::string pair_line_;
  ScalarGrid own_field_;
  uint64_t steps_ = 0, history_first_ = 0;
  size_t pending_ = 0;
  bool dirty_ = true;
  double balanced_at_ = 0;  // the atom count at the last `balance`
};

}  // namespace

bool lammps_available() { return true; }

MpiWorld lammps_mpi_start() {
  lammps_engine::ensure_mpi();
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
