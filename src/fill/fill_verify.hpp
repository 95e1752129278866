// The last word on a fill, by exact distances: spheres the field let
// through the surface moved in or removed, holes it hid near the wall
// given a sphere, then the metrics and the colours.
#pragma once
#include <optional>
#include <cstdint>

#include "pfill/boundary.hpp"
#include "pfill/fill.hpp"

namespace pfill {

/// Repairs containment of `particles` (spheres of `radius` in the mesh of
/// `boundary`, enclosing `volume`), fills the holes a sphere still fits in,
/// measures and colours them, and moves them into `result` (particles,
/// metrics, containment, holes_filled, warnings). `next_id` labels the
/// spheres it inserts.
/// Unequal spheres (`sizes`, mesh units; `radius` its smallest): holes take
/// a sphere of a class short of its share, and the result says how the
/// radii follow the distribution (FillResult::radii_fit); `size_caps`:
/// each class's most spheres (SizeDeficit::set_caps; empty: none).
void verify_fill(const Boundary& boundary, const Mesh& mesh, double volume, double radius,
                 const std::optional<RadiusDistribution>& sizes, const std::vector<size_t>& size_caps,
                 const FillOptions& o, ParticleSet particles, uint64_t& next_id, FillResult& result);

}  // namespace pfill
