// Which cells of the neighbour grid a sphere can reach: those within a cell
// of the object, by its signed distance field. The grid gives slots only to
// those (CellGrid::set_domain): most of a box around a round object lies
// outside it, and the slots are the engine's largest buffer (~550 MiB of a
// million-sphere fill on spot when every cell had them).
#pragma once
#include <cstdint>
#include <vector>

#include "pfill/grid.hpp"

namespace pfill {

/// One flag a cell (x fastest) of the grid of `dims` cells of edge
/// `cell_size` from `origin`: 1 where a field sample lies inside the object
/// or closer to its surface than a cell, or in one of the 26 cells around
/// such a cell; 0 elsewhere. Sound because the field's samples near the
/// surface hold exact distances (sdf.hpp), and a sphere, pushed back by
/// the wall once past it, never strays a cell outside.
std::vector<uint8_t> reachable_cells(const ScalarGrid& field, const Vec3& origin, double cell_size,
                                     const int dims[3]);

}  // namespace pfill
