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
  for (unsigned level = 0; level < levels_; ++level) {
    double cells = 1;
    for (int a = 0; a < 3; ++a) cells *= ((d[a] - 1) >> level) + 1;
    total += cells;
  }
  const std::vector<uint8_t> reachable =
      levels_ == 1 && field != nullptr && !field->values.empty() ? reachable_cells(*field, box.lo, cs, d)
                                                                 : std::vector<uint8_t>();
  blocks_ = levels_ > 1 ? 0
            : reachable.empty() ? static_cast<size_t>(total)
                                : static_cast<size_t>(std::count(reachable.begin(), reachable.end(), 1));
  const double slot_floats = slot_floats_for(d, total);
  if (slot_floats > 1.5e9)
    throw Error("engine: the neighbour grid would need " + std::to_string(static_cast<long long>(total)) +
                " cells; use a larger radius or a smaller domain");
  const double lo[3] = {box.lo.x, box.lo.y, box.lo.z};
  for (int a = 0; a < 3; ++a) {
    origin.s[a] = static_cast<float>(lo[a]);
    inv.s[a] = static_cast<float>(1 / cs);
    dims.s[a] = d[a];
  }
  origin.s[3] = inv.s[3] = 0.0f;
  dims.s[3] = 0;
  total_ = static_cast<size_t>(total);
  counts = device_.make_buffer(2 * total_ * sizeof(cl_uint), "cell counts");
  const size_t slot_bytes = static_cast<size_t>(slot_floats) * sizeof(cl_float);
  slots = device_.make_buffer(slot_bytes, "cell slots");
  // Zeroed once: lanes past a cell's count are read (then masked), so keep them finite.
  check_cl(device_.queue().enqueueFillBuffer(slots, cl_float(0), 0, slot_bytes), "clEnqueueFillBuffer", "cell slots");
  if (levels_ == 1) write_block_table(reachable);
  clear();
  has_domain_ = true;
}

// One level: a table word a cell, then the blocks of the reachable cells
// and one empty block the others share (cells.cl PF_NO_BLOCK); the table
// padded to 64 bytes, so that blocks keep the alignment of their chunks.
// Cell levels: every cell its block, one level after the other.
double CellGrid::slot_floats_for(const int d[3], double total) const {
  if (levels_ > 1) {
    double floats = 0;
    for (unsigned level = 0; level < levels_; ++level) {
      double cells = 1;
      for (int a = 0; a < 3; ++a) cells *= ((d[a] - 1) >> level) + 1;
      floats += cells * 5 * (level == 0 ? cell_capacity_ : capacity_up_);
    }
    return floats;
  }
  return static_cast<double>(table_words(static_cast<size_t>(total))) +
         static_cast<double>(blocks_ + 1) * 5 * static_cast<double>(cell_capacity_);
}

size_t CellGrid::table_words(size_t cells) { return (cells + 15) / 16 * 16; }

void CellGrid::write_block_table(const std::vector<uint8_t>& reachable) {
  const size_t block = 5 * cell_capacity_, first = table_words(total_);
  const cl_uint spare = static_cast<cl_uint>(first + blocks_ * block) | kNoBlock;
  std::vector<cl_uint> table(total_);
  size_t next = first;
  for (size_t cell = 0; cell < total_; ++cell) {
    if (!reachable.empty() && !reachable[cell]) {
      table[cell] = spare;
      continue;
    }
    table[cell] = static_cast<cl_uint>(next);
    next += block;
  }
  check_cl(device_.queue().enqueueWriteBuffer(slots, CL_TRUE, 0, total_ * sizeof(cl_uint), table.data()),
           "clEnqueueWriteBuffer", "cell slots' table");
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
