// The neighbour grid's device buffers (see cell_grid.hpp).
#include "engine/cell_grid.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/reachable_cells.hpp"
#include "pfill/device/device_error.hpp"
#include "pfill/error.hpp"

namespace pfill {

CellGrid::CellGrid(Device& device, double cell_size, size_t cell_capacity, unsigned levels, size_t capacity_up)
    : device_(device),
      cell_size_(cell_size),
      cell_capacity_(cell_capacity),
      levels_(std::max(levels, 1u)),
      capacity_up_(capacity_up > 0 ? capacity_up : cell_capacity) {
  touched_upto = device_.make_buffer(2 * sizeof(cl_uint), "cells to empty");
}

void CellGrid::set_domain(const Box3& box, const ScalarGrid* field) {
  const double cs = cell_size_;
  int d[3];
  for (int a = 0; a < 3; ++a) d[a] = std::max(1, static_cast<int>(std::ceil(box.size()[a] / cs)));
  double total = 0;
  for (unsigned level = 0; level < levels_; ++level) total += level_cells(d, level);
  if (total > 1.5e8)  // (8 bytes of counts and 4 of table a cell, slots or not)
    throw Error("engine: the neighbour grid would need " + std::to_string(static_cast<long long>(total)) +
                " cells; use a larger radius or a smaller domain");
  total_ = static_cast<size_t>(total);
  const std::vector<uint8_t> reachable = field != nullptr && !field->values.empty()
                                             ? reachable_cells(*field, box.lo, cs, d)
                                             : std::vector<uint8_t>(static_cast<size_t>(level_cells(d, 0)), 1);
  size_t slot_floats = 0;
  const std::vector<cl_uint> table = block_table(d, reachable, slot_floats);
  if (static_cast<double>(slot_floats) > 1.5e9)
    throw Error("engine: the neighbour grid would need " + std::to_string(blocks_) +
                " cells with slots; use a larger radius or a smaller domain");
  const double lo[3] = {box.lo.x, box.lo.y, box.lo.z};
  for (int a = 0; a < 3; ++a) {
    origin.s[a] = static_cast<float>(lo[a]);
    inv.s[a] = static_cast<float>(1 / cs);
    dims.s[a] = d[a];
  }
  origin.s[3] = inv.s[3] = 0.0f;
  dims.s[3] = 0;
  counts = device_.make_buffer(2 * total_ * sizeof(cl_uint), "cell counts");
  const size_t slot_bytes = slot_floats * sizeof(cl_float);
  slots = device_.make_buffer(slot_bytes, "cell slots");
  // Zeroed once: lanes past a cell's count are read (then masked), so keep them finite.
  check_cl(device_.queue().enqueueFillBuffer(slots, cl_float(0), 0, slot_bytes), "clEnqueueFillBuffer", "cell slots");
  check_cl(device_.queue().enqueueWriteBuffer(slots, CL_TRUE, 0, total_ * sizeof(cl_uint), table.data()),
           "clEnqueueWriteBuffer", "cell slots' table");
  clear();
  has_domain_ = true;
}

double CellGrid::level_cells(const int d[3], unsigned level) {
  double cells = 1;
  for (int a = 0; a < 3; ++a) cells *= ((d[a] - 1) >> level) + 1;
  return cells;
}

// The slots' table (cells.cl PF_NO_BLOCK): a word a cell of every level,
// padded to 64 bytes (the blocks keep their chunks' alignment), then a
// block for each cell a sphere can reach (a level-L cell where one of the
// level-0 cells under it is `reachable`) and one empty block the others
// share. Sets blocks_; `floats`: the slots' size.
std::vector<cl_uint> CellGrid::block_table(const int d[3], const std::vector<uint8_t>& reachable, size_t& floats) {
  std::vector<cl_uint> table(total_, 0);
  std::vector<uint8_t> used(total_, 0);
  size_t first = 0;
  for (unsigned level = 0; level < levels_; ++level) {
    const int n[3] = {((d[0] - 1) >> level) + 1, ((d[1] - 1) >> level) + 1, ((d[2] - 1) >> level) + 1};
    for (int z = 0; z < d[2]; ++z)
      for (int y = 0; y < d[1]; ++y)
        for (int x = 0; x < d[0]; ++x)
          if (reachable[static_cast<size_t>(x) + d[0] * (y + static_cast<size_t>(d[1]) * z)])
            used[first + static_cast<size_t>(x >> level) + n[0] * ((y >> level) + static_cast<size_t>(n[1]) * (z >> level))] = 1;
    first += static_cast<size_t>(level_cells(d, level));
  }
  size_t next = (total_ + 15) / 16 * 16;
  blocks_ = 0;
  first = 0;
  for (unsigned level = 0; level < levels_; ++level) {
    const size_t block = 5 * (level == 0 ? cell_capacity_ : capacity_up_);
    const size_t cells = static_cast<size_t>(level_cells(d, level));
    for (size_t cell = first; cell < first + cells; ++cell)
      if (used[cell]) table[cell] = static_cast<cl_uint>(next), next += block, ++blocks_;
    first += cells;
  }
  for (size_t cell = 0; cell < total_; ++cell)
    if (!used[cell]) table[cell] = static_cast<cl_uint>(next) | kNoBlock;
  floats = next + 5 * std::max(cell_capacity_, capacity_up_);
  return table;
}

void CellGrid::reserve(size_t cap) {
  touched = device_.make_buffer(2 * cap * sizeof(cl_uint), "cells first into");
  if (has_domain_) clear();  // the cells the last step filled were listed in the old `touched`
}

void CellGrid::clear() {
  check_cl(device_.queue().enqueueFillBuffer(counts, cl_uint(0), 0, 2 * total_ * sizeof(cl_uint)),
           "clEnqueueFillBuffer", "cell counts");
  check_cl(device_.queue().enqueueFillBuffer(touched_upto, cl_uint(0), 0, 2 * sizeof(cl_uint)),
           "clEnqueueFillBuffer", "cells to empty");
}

namespace {

// The bits of v (21 of them) spread to every third bit.
uint64_t spread_bits(uint64_t v) {
  v &= 0x1FFFFF;
  v = (v | v << 32) & 0x1F00000000FFFFull;
  v = (v | v << 16) & 0x1F0000FF0000FFull;
  v = (v | v << 8) & 0x100F00F00F00F00Full;
  v = (v | v << 4) & 0x10C30C30C30C30C3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

}  // namespace

uint64_t CellGrid::morton_key(const cl_float4& x) const {
  uint64_t key = 0;
  for (int a = 0; a < 3; ++a) {
    const double t = std::floor((x.s[a] - origin.s[a]) * inv.s[a]);
    const int c = static_cast<int>(std::clamp(t, 0.0, static_cast<double>(dims.s[a] - 1)));
    key |= spread_bits(static_cast<uint64_t>(c)) << a;
  }
  return key;
}

void CellGrid::require_domain() const {
  if (!has_domain_)
    throw Error("engine: no neighbour grid domain; call set_field() or set EngineParams::domain before stepping");
}

}  // namespace pfill
