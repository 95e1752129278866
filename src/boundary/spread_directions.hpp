// The directions of the rays the inside test casts.
#pragma once
#include <vector>

#include "pfill/vec3.hpp"

namespace pfill {

/// `count` unit vectors spread over the sphere (golden spiral, turned by
/// `offset`), then by a fixed irrational rotation so none lies in an axis
/// plane or along a mesh's natural symmetry directions.
std::vector<Vec3> spread_directions(int count, double offset);

}  // namespace pfill
