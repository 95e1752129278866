// The closed parts of a mesh's solid, from its triangles alone (issue 31:
// where no process builds a field, the fill still gives every part a
// birth site, as add_sites_per_part does on the field's 6-connected parts).
//
// Each connected component of the surface that encloses solid (its signed
// volume has the solid's sign) is a part; one that encloses a cavity (the
// other sign) belongs to the smallest enclosing part that contains it.
// The part of a point inside the solid is that of the surface nearest to
// it: the segment to the nearest surface point crosses no surface, so the
// point lies in the part that surface bounds.
//
// Where parts overlap (their union is the solid) each stays a part of its
// own, where the field sees one: such a union may get a site more.
#pragma once
#include <cstdint>
#include <vector>

#include "pfill/boundary.hpp"
#include "pfill/vec3.hpp"

namespace pfill {

class MeshParts {
 public:
  explicit MeshParts(const Boundary& boundary);

  size_t count() const { return parts_; }
  /// The part holding p, a point `depth` inside the solid (its exact depth).
  uint32_t part_at(const Vec3& p, double depth) const;

 private:
  const Boundary& boundary_;
  std::vector<uint32_t> component_of_triangle_;
  std::vector<uint32_t> part_of_component_;
  size_t parts_ = 0;
};

}  // namespace pfill
