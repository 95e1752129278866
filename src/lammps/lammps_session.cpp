// The LAMMPS instance of the LAMMPS engine: see lammps_session.hpp.
#ifdef PFILL_WITH_LAMMPS
#include "lammps/lammps_session.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "pfill/error.hpp"

namespace pfill {
namespace lammps_engine {
namespace {

void finalize_mpi() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
}

}  // namespace

void ensure_mpi() {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (initialized) return;
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  std::atexit(finalize_mpi);
}

SubDomain LammpsSession::subdomain() const {
  SubDomain d;
  const double* lo = static_cast<const double*>(lammps_extract_global(lmp_, "sublo"));
  const double* hi = static_cast<const double*>(lammps_extract_global(lmp_, "subhi"));
  for (int a = 0; a < 3; ++a) d.lo[a] = lo[a], d.hi[a] = hi[a];
  d.set = true;
  return d;
}

std::string num(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

LammpsSession::LammpsSession() {
  ensure_mpi();
  comm_ = MPI_COMM_WORLD;
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &ranks_);
  // PFILL_LAMMPS_LOG=FILE: LAMMPS' own log (rank 0), with each run's timing breakdown.
  const char* log = std::getenv("PFILL_LAMMPS_LOG");
  log_ = log && *log;
  const char* args[] = {"pfill", "-log", "none", "-screen", "none", "-nocite"};
  lmp_ = lammps_open(6, const_cast<char**>(args), comm_, nullptr);
  if (!lmp_) throw Error("LAMMPS could not be started");
  if (log_) command(std::string("log ") + log + " append");  // every engine of the fill into one file
}

LammpsSession::~LammpsSession() {
  if (lmp_) lammps_close(lmp_);
}

int LammpsSession::create_atoms(const std::vector<int>& tags, const std::vector<double>& x,
                                const std::vector<double>& v) {
  std::vector<int> types(tags.size(), 1);
  drop_ghosts();
  // Never a null id array, even for no atoms: with none LAMMPS numbers the
  // atoms itself (Atom::tag_extend, a collective the other ranks, given
  // ids, would not join).
  const int none = 1;
  const double nowhere[3] = {0, 0, 0};
  return lammps_create_atoms(lmp_, static_cast<int>(tags.size()), tags.empty() ? &none : tags.data(),
                             types.empty() ? &none : types.data(), x.empty() ? nowhere : x.data(),
                             v.empty() ? nowhere : v.data(), nullptr, 0);
}

/// Forget this rank's ghost atoms before atoms are created through the
/// library. LAMMPS stores ghosts after the owned atoms (indices nlocal to
/// nlocal + nghost - 1), and `lammps_create_atoms` (LAMMPS 29 Sep 2021)
/// writes each new atom at index nlocal without dropping the ghosts first,
/// as the create_atoms command (and delete_atoms, and the exchange) do: the
/// new atoms overwrite ghosts, nlocal + nghost then reaches one slot past
/// the last one written for each new atom, and its map_set (and the next
/// exchange's map_clear) hash the ids found in those slots (uninitialised
/// memory from the arrays' realloc: a negative id indexes the hash's buckets
/// out of bounds, the heap corruption once seen at 2 ranks; one rank with
/// `boundary f f f` has no ghosts). The ghosts are rebuilt by the next
/// `run pre yes` (a birth always makes the next run set up again);
/// lammps_create_atoms itself rebuilds the atom map (map_init, map_set)
/// from the owned atoms.
void LammpsSession::drop_ghosts() { *static_cast<int*>(lammps_extract_global(lmp_, "nghost")) = 0; }

void LammpsSession::delete_atoms(const std::vector<int>& tags) {
  // A group of the ids (in commands of a few hundred), deleted without
  // renumbering: the engine's tags stay.
  for (size_t k = 0; k < tags.size(); k += 400) {
    std::string cmd = "group pf_gone id";
    for (size_t j = k; j < std::min(tags.size(), k + 400); ++j) cmd += " " + std::to_string(tags[j]);
    command(cmd);
  }
  command("delete_atoms group pf_gone compress no");
  command("group pf_gone delete");
}

namespace {

/// Every rank's `mine`, one after the other in rank order, on every rank.
template <class T>
std::vector<T> gather_all(const std::vector<T>& mine, MPI_Datatype type, int ranks, MPI_Comm comm) {
  if (ranks == 1) return mine;
  int n = static_cast<int>(mine.size());
  std::vector<int> counts(static_cast<size_t>(ranks)), offsets(static_cast<size_t>(ranks), 0);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  for (int r = 1; r < ranks; ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
  std::vector<T> all(static_cast<size_t>(offsets.back() + counts.back()));
  MPI_Allgatherv(mine.data(), n, type, all.data(), counts.data(), offsets.data(), type, comm);
  return all;
}

}  // namespace

std::vector<double> LammpsSession::gather(const std::vector<double>& mine) const {
  return gather_all(mine, MPI_DOUBLE, ranks_, comm_);
}

std::vector<uint64_t> LammpsSession::gather(const std::vector<uint64_t>& mine) const {
  return gather_all(mine, MPI_UINT64_T, ranks_, comm_);
}

void LammpsSession::throw_if_any(const std::string& error) const {
  int from = error.empty() ? ranks_ : rank_;
  if (ranks_ > 1) MPI_Allreduce(MPI_IN_PLACE, &from, 1, MPI_INT, MPI_MIN, comm_);
  if (from == ranks_) return;
  if (ranks_ == 1) throw Error(error);
  int n = rank_ == from ? static_cast<int>(error.size()) : 0;
  MPI_Bcast(&n, 1, MPI_INT, from, comm_);
  std::string said = rank_ == from ? error : std::string(static_cast<size_t>(n), ' ');
  MPI_Bcast(&said[0], n, MPI_CHAR, from, comm_);
  throw Error(said);
}

}  // namespace lammps_engine
}  // namespace pfill
#endif
