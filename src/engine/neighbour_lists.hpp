// The neighbour lists on the device (kernels/cells.cl, cpu_lists.cl,
// gpu_lists.cl): the rows and their counts, where each list was built,
// the CPU form's packed-row spans and inner lists, the three request words,
// and the births linked in since the last step.
#pragma once
#include <CL/opencl.hpp>

#include <cstdint>
#include <vector>

#include "pfill/device/device.hpp"

namespace pfill {

struct ListLayout {
  size_t list_capacity = 0;  // entries a row (PF_LIST_CAP)
  size_t inner_capacity = 0; // inner lists: words a particle of their buffer (PF_INNER_CAP)
  bool newton = false;       // CPU form, each pair listed once: rows packed per pair_forces block
  bool inner = false;        // CPU form with inner lists (dynamic pruning)
  bool gpu = false;          // GPU form: rows interleaved by 32 particles, entries plain indices (gpu_lists.cl)
};

class NeighbourLists {
 public:
  NeighbourLists(Device& device, ListLayout layout);

  /// Buffers for `cap` particles and `blocks` pair_forces blocks (their
  /// force buffers); the lists are then invalid (the next step rebuilds).
  void reserve(size_t cap, size_t blocks);

  /// The request words rotate over three: step `steps` reads the one the
  /// step before raised (births and removals raise it too), raises the
  /// next, and clears the third for the step after.
  static cl_uint read_slot(uint64_t steps) { return static_cast<cl_uint>((steps + 2) % 3); }
  static cl_uint raise_slot(uint64_t steps) { return static_cast<cl_uint>(steps % 3); }
  static cl_uint clear_slot(uint64_t steps) { return static_cast<cl_uint>((steps + 1) % 3); }

  /// The rows pair_forces sorts first (linked births' rows, filled by
  /// atomics; -1: none).
  cl_int4 sort_rows() const;
  /// Particle `last` left: its count must read 0 (a linked birth counts up from there).
  void clear_count(size_t last);
  /// For tests: the first n particles' lists as neighbour indices, in row order (blocking).
  std::vector<std::vector<uint32_t>> read(size_t n) const;

  cl::Buffer rows, counts, origins;  // PF_ROW / PF_LIST_ROW rows, their counts, where each list was built
  cl::Buffer spans;                  // with newton: each packed row's first word and room (PF_LIST_ROW)
  cl::Buffer inner_rows, inner_counts, prune_origins;  // inner lists: rows, (count, touching), where pruned
  cl::Buffer requests;               // the three request words (PF_REQUEST_REBUILD / PF_REQUEST_PRUNE)
  bool valid = false;                // false: the next step rebuilds every list
  std::vector<int> newcomers;        // linked births since the last step (at most 4)

 private:
  cl::Buffer zeroed(size_t bytes, const char* what);

  Device& device_;
  ListLayout layout_;
};

}  // namespace pfill
