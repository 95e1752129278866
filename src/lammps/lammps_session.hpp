// One LAMMPS instance on MPI_COMM_WORLD, as the LAMMPS engine drives it
// (docs/lammps_engine.md): MPI started once, the instance opened and
// closed, commands, this rank's per-atom arrays, atoms created and deleted
// by tag, and the one collective the engine's reads need (a gather of every
// rank's values to every rank). The only header of pfill that includes
// mpi.h and LAMMPS' library.h (with LAMMPS_LIB_MPI and OMPI_SKIP_MPICXX).
#pragma once
#ifdef PFILL_WITH_LAMMPS
#define LAMMPS_LIB_MPI 1
#ifndef OMPI_SKIP_MPICXX
#define OMPI_SKIP_MPICXX 1
#endif
#include <mpi.h>
#include <library.h>

#include <cstdint>
#include <string>
#include <vector>

namespace pfill {
namespace lammps_engine {

/// MPI_Init_thread unless MPI runs already (then MPI_Finalize at exit).
void ensure_mpi();

/// A rank's box in LAMMPS' domain decomposition (`sublo`, `subhi`).
struct SubDomain {
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  bool set = false;  ///< false until an engine ran
};

/// v with all 17 digits, for a LAMMPS command.
std::string num(double v);

class LammpsSession {
 public:
  /// Starts MPI if needed and opens LAMMPS on MPI_COMM_WORLD (no log, no screen).
  LammpsSession();
  ~LammpsSession();
  LammpsSession(const LammpsSession&) = delete;
  LammpsSession& operator=(const LammpsSession&) = delete;

  void* handle() const { return lmp_; }
  MPI_Comm comm() const { return comm_; }
  int rank() const { return rank_; }
  int ranks() const { return ranks_; }
  int version() const { return lammps_version(lmp_); }
  /// PFILL_LAMMPS_LOG is set: runs print LAMMPS' timing breakdown (`post yes`) to it.
  bool logging() const { return log_; }

  void command(const std::string& c) { lammps_command(lmp_, c.c_str()); }
  void commands(const std::string& lines) { lammps_commands_string(lmp_, lines.c_str()); }

  /// The number of atoms this rank owns.
  int nlocal() const { return *static_cast<int*>(lammps_extract_global(lmp_, "nlocal")); }
  /// This rank's box in the domain decomposition now.
  SubDomain subdomain() const;
  /// The atoms on all ranks, as LAMMPS counts them.
  double natoms() const { return lammps_get_natoms(lmp_); }
  /// This rank's per-atom array `name` ("id", "x", "v", "radius", ...), owned atoms first.
  template <class T>
  T atoms(const char* name) const {
    return static_cast<T>(lammps_extract_atom(lmp_, name));
  }

  /// n atoms of type 1 with the given tags, positions and velocities (3 n
  /// each; n may differ between ranks, and be 0); each rank keeps those in
  /// its sub-domain of the atoms every rank passed.
  /// Returns how many were created over all ranks. The new atoms this rank
  /// owns are its indices [nlocal before, nlocal after).
  int create_atoms(const std::vector<int>& tags, const std::vector<double>& x, const std::vector<double>& v);

  /// Deletes the atoms with these tags (on whichever rank owns them), without
  /// renumbering the others (`delete_atoms ... compress no`).
  void delete_atoms(const std::vector<int>& tags);

  /// Every rank's `mine`, in rank order, on every rank (an MPI_Allgatherv).
  std::vector<double> gather(const std::vector<double>& mine) const;
  std::vector<uint64_t> gather(const std::vector<uint64_t>& mine) const;

  /// Where any rank met an error (`error` not empty there), every rank
  /// throws pfill::Error with the message of the lowest such rank, so that
  /// an error met on one rank's share is said, by rank 0, and ends every
  /// rank alike. Collective (one MPI_Allreduce; two MPI_Bcast on an error).
  void throw_if_any(const std::string& error) const;

 private:
  void drop_ghosts();

  void* lmp_ = nullptr;
  MPI_Comm comm_;
  int rank_ = 0, ranks_ = 1;
  bool log_ = false;
};

}  // namespace lammps_engine
}  // namespace pfill
#endif
