// The last word on a fill, by exact distances: spheres the field let
// through the surface moved in or removed, holes it hid near the wall
// given a sphere, then the metrics and the colours.
#pragma once
#include <optional>
#include <cstdint>

#include "pfill/boundary.hpp"
#include "pfill/fill.hpp"
#include "pfill/particle_share.hpp"

namespace pfill {

/// Repairs containment of `particles` (spheres of `radius` in the mesh of
/// `boundary`, enclosing `volume`), fills the holes a sphere still fits in,
/// measures and colours them, and moves them into `result` (particles,
/// metrics, containment, holes_filled, warnings). `next_id` labels the
/// spheres it inserts. Held in parts (`share` over several processes; the
/// LAMMPS engine at P > 1 ranks): `particles` are this process's own, and
/// so are `result.particles`; the metrics and counts are of the whole.
/// Collective.
/// Unequal spheres (`sizes`, mesh units; `radius` its smallest): holes take
/// a sphere of a class short of its share, and the result says how the
/// radii follow the distribution (FillResult::radii_fit); `size_caps`:
/// each class's most spheres (SizeDeficit::set_caps; empty: none).
void verify_fill(const Boundary& boundary, const Mesh& mesh, double volume, double radius,
                 const std::optional<RadiusDistribution>& sizes, const std::vector<size_t>& size_caps,
                 const FillOptions& o, ParticleSet particles, const ParticleShare& share, uint64_t& next_id,
                 FillResult& result);

}  // namespace pfill
