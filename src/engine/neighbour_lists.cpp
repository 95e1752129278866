// The neighbour lists' device buffers (see neighbour_lists.hpp).
#include "engine/neighbour_lists.hpp"

#include <algorithm>

#include "pfill/device/device_error.hpp"

namespace pfill {

NeighbourLists::NeighbourLists(Device& device, ListLayout layout) : device_(device), layout_(layout) {
  requests = zeroed(3 * sizeof(cl_uint), "list rebuild requests");
}

cl::Buffer NeighbourLists::zeroed(size_t bytes, const char* what) {
  cl::Buffer b = device_.make_buffer(bytes, what);
  check_cl(device_.queue().enqueueFillBuffer(b, cl_uint(0), 0, bytes), "clEnqueueFillBuffer", what);
  return b;
}

void NeighbourLists::reserve(size_t cap, size_t blocks) {
  const size_t row = layout_.list_capacity;
  // With newton the CPU form packs a block's rows into its PF_ROW_STRIDE
  // (row + 8) words a particle; blocks may reach `blocks` particles past
  // the capacity; 8 more words for the pair loop's eights past the last row.
  const size_t words = layout_.newton ? (cap + blocks) * (row + 8) + 8 : cap * row;
  // Zeroed: the CPU pair loop reads a row's entries in eights, past its
  // count too (then masks them), so every entry must be an index below
  // the capacity (the build pads with the row's own particle).
  rows = zeroed(words * sizeof(cl_uint), "neighbour lists");
  spans = zeroed((layout_.newton ? cap : 1) * sizeof(cl_uint2), "neighbour list rows");
  // Counts past the last particle stay 0: a linked birth counts up from there.
  counts = zeroed(cap * sizeof(cl_uint), "neighbour list counts");
  origins = device_.make_buffer(cap * sizeof(cl_float4), "neighbour list origins");
  const size_t inner_cap = layout_.inner ? cap : 1;  // (a word each when unused)
  // Packed rows (see pair_forces): 8 entries of slack for the pair loop's
  // eights past the last row's end; zeroed, as the lists are.
  inner_rows = zeroed((inner_cap * layout_.inner_capacity + 8) * sizeof(cl_uint), "inner neighbour lists");
  // Read only after a pruning wrote them: the first step after this prunes,
  // as does the step after any linked birth or removal.
  inner_counts = device_.make_buffer(inner_cap * sizeof(cl_uint2), "inner neighbour list counts");
  prune_origins = device_.make_buffer(inner_cap * sizeof(cl_float4), "inner neighbour list origins");
  valid = false;
}

cl_int4 NeighbourLists::sort_rows() const {
  cl_int4 r;
  for (int k = 0; k < 4; ++k) r.s[k] = k < static_cast<int>(newcomers.size()) ? newcomers[k] : -1;
  return r;
}

void NeighbourLists::clear_count(size_t last) {
  check_cl(device_.queue().enqueueFillBuffer(counts, cl_uint(0), last * sizeof(cl_uint), sizeof(cl_uint)),
           "clEnqueueFillBuffer", "neighbour list count");
}

namespace {

template <typename T>
std::vector<T> read_all(Device& device, const cl::Buffer& b, const char* what) {
  std::vector<T> out(b.getInfo<CL_MEM_SIZE>() / sizeof(T));
  check_cl(device.queue().enqueueReadBuffer(b, CL_TRUE, 0, out.size() * sizeof(T), out.data()),
           "clEnqueueReadBuffer", what);
  return out;
}

}  // namespace

std::vector<std::vector<uint32_t>> NeighbourLists::read(size_t n) const {
  const size_t cap = layout_.list_capacity;
  const auto words = read_all<cl_uint>(device_, rows, "neighbour lists");
  const auto count = read_all<cl_uint>(device_, counts, "neighbour list counts");
  const auto span = read_all<cl_uint2>(device_, spans, "neighbour list rows");
  std::vector<std::vector<uint32_t>> out(n);
  for (size_t i = 0; i < n; ++i) {
    const size_t m = std::min<size_t>(count[i], cap);
    for (size_t k = 0; k < m; ++k) {
      if (layout_.gpu)  // gpu_lists.cl PF_ROW, PF_AT
        out[i].push_back(words[(i / 32) * cap * 32 + (i % 32) * 4 + (k >> 2) * 128 + (k & 3)]);
      else  // cpu_lists.cl PF_LIST_ROW; entries 16 j (PF_ENTRY)
        out[i].push_back(words[(layout_.newton ? span[i].s[0] : i * cap) + k] >> 4);
    }
  }
  return out;
}

}  // namespace pfill
