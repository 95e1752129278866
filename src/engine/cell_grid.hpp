// The neighbour grid on the device (kernels/cells.cl): its geometry (one
// grid, or nested levels for unequal spheres: EngineConstants::cell_levels),
// two sets of count words taken in turn by the step's parity, the slots, and
// by parity the cell each particle was first into and how many particles
// were listed, which the next step empties.
#pragma once
#include <CL/opencl.hpp>

#include <cstdint>
#include <vector>

#include "pfill/device/device.hpp"
#include "pfill/grid.hpp"
#include "pfill/vec3.hpp"

namespace pfill {

class CellGrid {
 public:
  /// `levels` nested grids, level L's cells 2^L cell_size wide; level 0's
  /// cells hold `cell_capacity` particles, the others' `capacity_up`.
  CellGrid(Device& device, double cell_size, size_t cell_capacity, unsigned levels = 1, size_t capacity_up = 0);

  /// The grid over `box`: cells of edge exactly the cell size (the grid
  /// may reach a little past the box; particles outside clamp in), empty.
  /// Level L has ((dims - 1) >> L) + 1 cells a side, numbered after the
  /// levels below it (cells.cl pf_level_at).
  /// With a `field` (the wall): slots only for the cells a sphere can
  /// reach (reachable_cells.hpp), found through a table (cells.cl
  /// PF_NO_BLOCK); without one, every cell has slots.
  void set_domain(const Box3& box, const ScalarGrid* field = nullptr);
  /// Room for `cap` particles' first-into words (empties the cells).
  void reserve(size_t cap);
  /// Both sets of counts empty, and nothing left for a step to empty.
  void clear();
  /// Throws unless set_domain was called.
  void require_domain() const;
  bool has_domain() const { return has_domain_; }

  /// Step `steps`'s set of count words (every level's cells): its first word.
  cl_uint base(uint64_t steps) const { return static_cast<cl_uint>((steps % 2) * total_); }
  cl_uint total() const { return static_cast<cl_uint>(total_); }
  /// The Morton (Z-order) key of the cell holding `x`, clamped into the
  /// grid as the kernels clamp (cells.cl pf_cell_of).
  uint64_t morton_key(const cl_float4& x) const;

  cl_float4 origin{}, inv{};  // the grid's corner; 1 / cell edge
  cl_int4 dims{};
  cl::Buffer counts, slots, touched, touched_upto;

 private:
  Device& device_;
  double cell_size_;
  size_t cell_capacity_;
  unsigned levels_;
  size_t capacity_up_;
  static double level_cells(const int d[3], unsigned level);
  std::vector<cl_uint> block_table(const int d[3], const std::vector<uint8_t>& reachable, size_t& floats);

  static constexpr cl_uint kNoBlock = 0x80000000u;  // cells.cl PF_NO_BLOCK
  size_t total_ = 0;
  size_t blocks_ = 0;  // cells with slots of their own, over all levels
  bool has_domain_ = false;
};

}  // namespace pfill
