// The fill's ProcessGroup on MPI_COMM_WORLD (process_group.hpp): the
// ranks of the LAMMPS engine, for what runs after its last engine is gone
// (the exact check, the metrics, the output; issue 31).
#ifdef PFILL_WITH_LAMMPS
#include <climits>
#include <memory>

#include "lammps/lammps_session.hpp"
#include "pfill/engine/process_group.hpp"
#include "pfill/error.hpp"
#include "pfill/lammps.hpp"

namespace pfill {
namespace {

/// MPI counts are ints: a message past 2 GiB says what to do instead.
int count_of(size_t bytes) {
  if (bytes > static_cast<size_t>(INT_MAX))
    throw Error("a message between MPI ranks would exceed 2 GiB: write a file per rank (-o with %r, pfill join)");
  return static_cast<int>(bytes);
}

/// Where each rank's part begins in the whole, from their counts; returns the whole's size.
size_t offsets_of(const std::vector<int>& counts, std::vector<int>& offsets) {
  offsets.assign(counts.size(), 0);
  size_t total = 0;
  for (size_t r = 0; r < counts.size(); ++r) {
    offsets[r] = count_of(total);
    total += static_cast<size_t>(counts[r]);
  }
  count_of(total);
  return total;
}

class MpiGroup final : public ProcessGroup {
 public:
  MpiGroup() {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  void sum(std::vector<double>& v) override { reduce(v, MPI_SUM); }
  void max(std::vector<double>& v) override { reduce(v, MPI_MAX); }

  Bytes all_gather(const Bytes& mine) override {
    int n = count_of(mine.size());
    std::vector<int> counts(static_cast<size_t>(size_)), offsets;
    MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
    Bytes all(offsets_of(counts, offsets));
    MPI_Allgatherv(mine.data(), n, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, MPI_COMM_WORLD);
    return all;
  }

  Bytes gather_to_first(const Bytes& mine) override {
    int n = count_of(mine.size());
    std::vector<int> counts(static_cast<size_t>(size_)), offsets;
    MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    Bytes all;
    if (rank_ == 0) all.resize(offsets_of(counts, offsets));
    MPI_Gatherv(mine.data(), n, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, 0, MPI_COMM_WORLD);
    return all;
  }

  Bytes exchange(const std::vector<Bytes>& to) override {
    std::vector<int> send(static_cast<size_t>(size_)), recv(send.size()), send_at, recv_at;
    Bytes out;
    for (size_t r = 0; r < send.size(); ++r) {
      send[r] = count_of(to.at(r).size());
      out.insert(out.end(), to[r].begin(), to[r].end());
    }
    offsets_of(send, send_at);
    MPI_Alltoall(send.data(), 1, MPI_INT, recv.data(), 1, MPI_INT, MPI_COMM_WORLD);
    Bytes in(offsets_of(recv, recv_at));
    MPI_Alltoallv(out.data(), send.data(), send_at.data(), MPI_BYTE, in.data(), recv.data(), recv_at.data(),
                  MPI_BYTE, MPI_COMM_WORLD);
    return in;
  }

 private:
  void reduce(std::vector<double>& v, MPI_Op op) {
    if (!v.empty()) MPI_Allreduce(MPI_IN_PLACE, v.data(), count_of(v.size()), MPI_DOUBLE, op, MPI_COMM_WORLD);
  }
  int rank_ = 0, size_ = 1;
};

}  // namespace

std::shared_ptr<ProcessGroup> lammps_process_group() {
  int initialized = 0, size = 1;
  MPI_Initialized(&initialized);
  if (initialized) MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size == 1) return std::make_shared<ProcessGroup>();
  return std::make_shared<MpiGroup>();
}

}  // namespace pfill
#endif
