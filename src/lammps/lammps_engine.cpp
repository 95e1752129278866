// The LAMMPS engine (docs/lammps_engine.md): a ParticleEngine whose
// particles live in a LAMMPS instance on MPI_COMM_WORLD. LAMMPS owns the
// domain decomposition, the neighbour lists, the halo exchange, the
// migration of atoms between ranks; pfill's own step rules (the pair
// forces over LAMMPS' lists, the integration, the wall) run in a `fix
// external pf/callback` on each rank's own atoms (step_callback.hpp). This
// file is the engine class: it ties
// together the LAMMPS instance (lammps_session.hpp), the settings handed
// to it (lammps_settings.hpp), the engine's indices (particle_book.hpp,
// atom_indices.hpp),
// that callback and the reads over ranks (engine_reads.hpp): births,
// removals, runs.
//
// SPMD: every rank makes the same calls with the same arguments (the fill's
// host loop runs on every rank), so the engine's count and tags are the
// same everywhere; each atom carries its index and id (atom_indices.hpp),
// so no rank keeps a record of every particle; each rank creates only the
// births it decided, in its sub-domain (add_decided_particles); reads and
// records are reductions. The births' room test sees only this rank's
// atoms and a halo (birth_view).
#ifdef PFILL_WITH_LAMMPS
#include <algorithm>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "lammps/atom_indices.hpp"
#include "lammps/birth_tally.hpp"
#include "lammps/halo_views.hpp"
#include "lammps/engine_reads.hpp"
#include "lammps/lammps_session.hpp"
#include "lammps/lammps_settings.hpp"
#include "lammps/new_atoms.hpp"
#include "lammps/particle_book.hpp"
#include "lammps/step_callback.hpp"
#include "pfill/error.hpp"
#include "pfill/lammps.hpp"

namespace pfill {
namespace {

using lammps_engine::LammpsSession;
using lammps_engine::num;
using lammps_engine::ParticleBook;
using lammps_engine::StepCallback;

class LammpsEngine final : public ParticleEngine {
 public:
  explicit LammpsEngine(const EngineParams& params)
      : params_(params),
        constants_(lammps_engine::checked_constants(params)),
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
    share_field(own_field_);
  }

  /// No copy, also with a wall offset: the callback adds it as it reads (band_field.hpp).
  void share_field(const ScalarGrid& field) override {
    step_.set_field(field, params_.wall_offset, box_made_);
    box_on_field(field);
  }
  /// Each rank computes only the bricks near the wall its atoms reach (band_field.hpp).
  size_t field_bytes() const override { return step_.field_bytes(); }
  void share_exact_field(const ExactField& field) override {
    step_.set_field(field, params_.wall_offset, box_made_);
    box_on_field(field.lattice());
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
    const int first_tag = book_.new_tags(ps.size());
    lammps_engine::NewAtoms atoms;
    for (size_t k = 0; k < ps.size(); ++k) atoms.add(first_tag + static_cast<int>(k), ps[k], mass_of(ps[k]));
    create(atoms, ps.size(), first_tag, first);  // each rank keeps those in its sub-domain
    return first;
  }

  /// Each rank passes lammps_create_atoms only the members it decided (its
  /// sub-domain's), each with its tag and index from its place in the
  /// batch; no rank sees the whole batch.
  size_t add_decided_particles(const std::vector<Particle>& mine, const std::vector<size_t>& places,
                               size_t count) override {
    flush();
    const size_t first = book_.size();
    if (count == 0) return first;
    if (!box_made_) make_box(bounds_over_ranks(mine));
    // Each rank checks its own; an error any rank meets ends every rank alike.
    std::string error;
    if (places.size() != mine.size())
      error = "lammps engine: " + std::to_string(mine.size()) + " particles given with " +
              std::to_string(places.size()) + " places";
    for (size_t k = 0; k < mine.size() && error.empty(); ++k) {
      error = particle_error(mine[k]);
      if (error.empty() && places[k] >= count)
        error = "lammps engine: a place " + std::to_string(places[k]) + " past its batch of " + std::to_string(count);
    }
    lmp_->throw_if_any(error);
    check_places_over_ranks(places, count);
    const int first_tag = book_.new_tags(count);
    lammps_engine::NewAtoms atoms;
    for (size_t k = 0; k < mine.size(); ++k)
      atoms.add(first_tag + static_cast<int>(places[k]), mine[k], mass_of(mine[k]));
    atoms.sort_by_tag();
    lammps_engine::BirthTally& tally = lammps_engine::birth_tally();
    tally.outside += lammps_engine::share_strays(*lmp_, atoms);
    tally.batches += 1, tally.newborns += count, tally.passed += atoms.size();
    create(atoms, count, first_tag, first);
    return first;
  }

  /// The book says who goes and who moves (the last into each hole); each
  /// rank finds them among its own atoms.
  void remove_particles(std::vector<size_t> indices) override {
    flush();
    const lammps_engine::Removal r = book_.remove(std::move(indices));
    if (r.gone.empty()) return;
    const std::unordered_set<size_t> gone(r.gone.begin(), r.gone.end());
    const std::unordered_map<size_t, size_t> moves(r.moves.begin(), r.moves.end());
    const lammps_engine::AtomIndices own(*lmp_);
    const int* tag = lmp_->atoms<int*>("id");
    std::vector<double> mine;
    for (int i = 0; i < own.count; ++i) {
      const size_t index = static_cast<size_t>(own.index[i]);
      if (gone.count(index)) {
        mine.push_back(tag[i]);
      } else if (const auto m = moves.find(index); m != moves.end()) {
        own.index[i] = static_cast<int>(m->second);
      }
    }
    std::vector<int> tags;  // the same on every rank (the lost are on none)
    for (double t : lmp_->gather(mine)) tags.push_back(static_cast<int>(t));
    std::sort(tags.begin(), tags.end());
    if (!tags.empty()) lmp_->delete_atoms(tags);
    for (int t : tags) step_.flagged_tags().erase(t);
    dirty_ = true;
  }

  void run_steps(size_t k) override { pending_ += k; }

  std::vector<StepRecord> read_history() override {
    flush();
    step_.fire().take_in_flight(steps_);  // as the OpenCL engine's finalize_history
    std::vector<StepRecord> out = lammps_engine::reduce_history(*lmp_, step_.take_history(), history_first_);
    history_first_ += out.size();
    return out;
  }

  std::vector<Particle> read_particles() override {
    flush();
    return lammps_engine::gather_particles(*lmp_, book_.size(), params_, box_.centre());
  }

  std::vector<size_t> sort_by_cells() override {
    // LAMMPS keeps its own atoms in spatial order (atom_modify sort); the
    // engine's indices are its own and stay (no order returned). FIRE's
    // records in flight are taken in, as the OpenCL engine finishes its
    // steps in flight to sort.
    flush();
    step_.fire().take_in_flight(steps_);
    return {};
  }

  std::vector<size_t> flagged_particles() override {
    flush();
    return lammps_engine::gather_flagged(*lmp_, book_.size(), step_.flagged_tags());
  }

  void clear_flags() override { step_.flagged_tags().clear(); }

  /// At P > 1: this rank's atoms and the others' within `reach` of its
  /// sub-domain, whose sites it decides (halo_views.hpp); no gather.
  BirthView birth_view(double reach, bool complete) override {
    flush();
    if (complete || lmp_->ranks() == 1) return ParticleEngine::birth_view(reach, complete);
    return lammps_engine::birth_halo(*lmp_, reach);
  }
  /// At P > 1: this rank's atoms and the others' within `reach`
  /// (halo_views.hpp). Atoms LAMMPS lost are in no view: flagged_particles
  /// names them for removal.
  LocalView local_view(double reach) override {
    flush();
    if (lmp_->ranks() == 1) return ParticleEngine::local_view(reach);
    return lammps_engine::local_halo(*lmp_, params_, reach);
  }

  void sum_over_processes(std::vector<int>& counts) override {
    if (lmp_->ranks() > 1 && !counts.empty())
      MPI_Allreduce(MPI_IN_PLACE, counts.data(), static_cast<int>(counts.size()), MPI_INT, MPI_SUM, lmp_->comm());
  }
  void gather_over_processes(std::vector<uint64_t>& values) override {
    if (lmp_->ranks() > 1) values = lmp_->gather(values);
  }
  std::shared_ptr<ProcessGroup> process_group() const override { return lammps_process_group(); }
  /// FIRE (fire_minimiser.hpp): afresh at the next step, on every rank alike.
  void restart_minimiser() override {
    flush();
    step_.fire().restart(steps_);
  }
  MinimiserState minimiser_state() override {
    flush();
    step_.fire().take_in_flight(steps_);
    return step_.fire().state();
  }

  /// Each rank types its own atoms by their part (step_callback.hpp's
  /// types); the next run's set-up gives the ghosts their types.
  std::optional<size_t> hold(const std::function<StepPart(const Vec3&)>& part_of) override {
    flush();
    const int n = lmp_->nlocal();
    double** x = lmp_->atoms<double**>("x");
    int* type = lmp_->atoms<int*>("type");
    static const int kTypeOf[] = {lammps_engine::kMovingType, lammps_engine::kHeldType, lammps_engine::kOutType};
    long long taking_part = 0;
    for (int i = 0; i < n; ++i) {
      type[i] = kTypeOf[static_cast<int>(part_of(Vec3{x[i][0], x[i][1], x[i][2]}))];
      taking_part += type[i] != lammps_engine::kOutType;
    }
    MPI_Allreduce(MPI_IN_PLACE, &taking_part, 1, MPI_LONG_LONG, MPI_SUM, lmp_->comm());
    step_.set_holding(true);
    dirty_ = true;
    return static_cast<size_t>(taking_part);
  }
  void release_hold() override {
    flush();
    if (!step_.holding()) return;
    int* type = lmp_->atoms<int*>("type");
    for (int i = 0, n = lmp_->nlocal(); i < n; ++i) type[i] = lammps_engine::kMovingType;
    step_.set_holding(false);
    dirty_ = true;
  }

  size_t size() const override { return book_.size(); }
  uint64_t steps_done() const override { return steps_ + pending_; }

 private:
  /// The box LAMMPS decomposes, the potential, the lists and the
  /// callback's fix (lammps_settings.hpp).
  void make_box(const Box3& inner) {
    const lammps_engine::BoxSettings b = lammps_engine::set_up_box(*lmp_, params_, constants_, inner, "pf_step");
    box_ = b.box;
    for (int a = 0; a < 3; ++a) lo_[a] = b.lo[a], hi_[a] = b.hi[a];
    step_.set_clamp(lo_, hi_);
    pair_line_ = b.describe;
    step_.install("pf_step");
    box_made_ = true;
  }

  /// The first field gives the box LAMMPS decomposes.
  void box_on_field(const ScalarGrid& f) {
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
      lmp_->command("run " + std::to_string(k) + " pre " + (dirty_ ? "yes" : "no") + " post " +
                    (lmp_->logging() ? "yes" : "no"));
      steps_ += k;
      pending_ -= k;
      dirty_ = false;
    }
  }

  static bool finite(const Particle& p) { return is_finite(p.position) && is_finite(p.velocity); }

  /// What LAMMPS could not take of p, in one line; empty where it can.
  std::string particle_error(const Particle& p) const {
    if (!finite(p)) return "lammps engine: a particle's position or velocity is not a finite number";
    if (!(p.radius > 0) || p.radius > constants_.max_radius * (1 + 1e-9))
      return "lammps engine: a particle's radius " + num(p.radius) + " is not in (0, max_radius]";
    if (p.id > lammps_engine::kLargestAtomId)
      return "lammps engine: a particle's id " + std::to_string(p.id) +
             " is past 2^53, which the atom's id property (a double) cannot hold exactly; number the particles from 1";
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

  /// That the ranks' places name each of 0..count-1 once, by the sums of
  /// the places, their squares and their count over the ranks (modulo
  /// 2^64; one MPI_Allreduce), so that no rank needs every place: two
  /// atoms with one tag would stop LAMMPS at the next run.
  void check_places_over_ranks(const std::vector<size_t>& places, size_t count) const {
    uint64_t sums[3] = {places.size(), 0, 0};
    for (size_t p : places) sums[1] += p, sums[2] += static_cast<uint64_t>(p) * p;
    // 0 + 1 + ... + (c - 1) = (c - 1) c / 2 and the sum of their squares
    // (c - 1) c (2c - 1) / 6, modulo 2^64 as the sums: each division taken
    // from the factor it divides before the products wrap.
    uint64_t f[3] = {count - 1, count, 2 * count - 1};
    const uint64_t sum = f[0] % 2 == 0 ? f[0] / 2 * f[1] : f[1] / 2 * f[0];
    for (uint64_t d : {2, 3})
      for (uint64_t& x : f)
        if (x % d == 0) {
          x /= d;
          break;
        }
    const uint64_t expected[3] = {count, count == 0 ? 0 : sum, count == 0 ? 0 : f[0] * f[1] * f[2]};
    MPI_Allreduce(MPI_IN_PLACE, sums, 3, MPI_UINT64_T, MPI_SUM, lmp_->comm());
    if (sums[0] != expected[0] || sums[1] != expected[1] || sums[2] != expected[2])
      throw Error("lammps engine: the ranks gave " + std::to_string(sums[0]) + " members of a batch of " +
                  std::to_string(count) + ", not each place once");
  }

  /// Creates the atoms (collective) and books them; `n`: how many the
  /// ranks meant to create, with tags from first_tag and indices from
  /// first_index (the book's next).
  void create(const lammps_engine::NewAtoms& atoms, size_t n, int first_tag, size_t first_index) {
    const int made = lammps_engine::create_new_atoms(*lmp_, atoms, first_tag, first_index);
    if (made != static_cast<int>(n))
      throw Error("lammps engine: " + std::to_string(n) + " particles given, " + std::to_string(made) + " created");
    book_.added(n);
    dirty_ = true;
  }

  bool inside_box(const Vec3& p) const {
    return p.x >= lo_[0] && p.y >= lo_[1] && p.z >= lo_[2] && p.x <= hi_[0] && p.y <= hi_[1] && p.z <= hi_[2];
  }

  EngineParams params_;
  EngineConstants constants_;
  std::unique_ptr<LammpsSession> lmp_;
  StepCallback step_;  // after lmp_: it holds a reference to it
  ParticleBook book_;  // the count and the next tag, the same on every rank
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

std::unique_ptr<ParticleEngine> make_lammps_engine(const EngineParams& params) {
  return std::make_unique<LammpsEngine>(params);
}

std::function<std::unique_ptr<ParticleEngine>(const EngineParams&)> lammps_engine_factory() {
  return [](const EngineParams& p) { return make_lammps_engine(p); };
}

}  // namespace pfill
#endif
