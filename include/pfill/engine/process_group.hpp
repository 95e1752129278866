/// @file process_group.hpp
/// @brief The processes one fill runs on (issue 31): one process (the OpenCL
/// and reference engines, LAMMPS at one rank), or the MPI ranks of the
/// LAMMPS engine. The fill's last steps (the exact check, the metrics, the
/// output) run after the engines are gone and work on each process's own
/// spheres; this is how they reach the others: sums and maxima, a gather
/// of records to every process or to the first, and an exchange of records
/// between pairs of processes (the halos). Every call is collective: each
/// process makes the same calls in the same order (SPMD). This base class
/// is the group of one process.
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

namespace pfill {

/// Raw records (fixed-size structs, packed with to_bytes/from_bytes).
using Bytes = std::vector<uint8_t>;

class ProcessGroup {
 public:
  virtual ~ProcessGroup() = default;
  virtual int rank() const { return 0; }
  virtual int size() const { return 1; }
  /// Element-wise sums, maxima of `values` over the processes, in place
  /// (each process passes as many).
  virtual void sum(std::vector<double>& values) { (void)values; }
  virtual void max(std::vector<double>& values) { (void)values; }
  /// Every process's `mine`, concatenated in process order, on every process.
  virtual Bytes all_gather(const Bytes& mine) { return mine; }
  /// Every process's `mine` concatenated in process order on the first
  /// (rank 0); the others get nothing back.
  virtual Bytes gather_to_first(const Bytes& mine) { return mine; }
  /// Sends `to[p]` to process p (`to` has size() entries); returns what
  /// every process sent here, concatenated in process order.
  virtual Bytes exchange(const std::vector<Bytes>& to) { return to.at(0); }

  bool alone() const { return size() == 1; }
  double sum(double v) {
    std::vector<double> one{v};
    sum(one);
    return one[0];
  }
  double max(double v) {
    std::vector<double> one{v};
    max(one);
    return one[0];
  }
  double min(double v) { return -max(-v); }
};

/// Appends `records` to `out` as raw bytes (T: trivially copyable).
template <class T>
void to_bytes(const std::vector<T>& records, Bytes& out) {
  const auto* b = reinterpret_cast<const uint8_t*>(records.data());
  out.insert(out.end(), b, b + records.size() * sizeof(T));
}

/// The records `bytes` holds (a whole number of T).
template <class T>
std::vector<T> from_bytes(const Bytes& bytes) {
  std::vector<T> records(bytes.size() / sizeof(T));
  if (!records.empty()) std::copy(bytes.begin(), bytes.begin() + static_cast<long>(records.size() * sizeof(T)),
                                  reinterpret_cast<uint8_t*>(records.data()));
  return records;
}

}  // namespace pfill
