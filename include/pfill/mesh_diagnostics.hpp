/// @file mesh_diagnostics.hpp
/// @brief What `pfill info` reports about a mesh: size, topology (closed or
/// not, holes, non-manifold edges, genus), orientation, volume and area, and
/// the particle radius that fits a given count.
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "pfill/mesh.hpp"
#include "pfill/winding_sweep.hpp"

namespace pfill {

struct MeshDiagnostics {
  size_t vertices = 0;            ///< vertices used by some triangle
  size_t triangles = 0;
  Box3 bounds;
  size_t components = 0;          ///< connected through shared vertices
  size_t edges = 0;               ///< distinct undirected edges
  size_t boundary_edges = 0;      ///< edges of exactly one triangle
  size_t boundary_loops = 0;      ///< holes: closed chains of boundary edges
  size_t non_manifold_edges = 0;  ///< edges of three or more triangles
  size_t misoriented_edges = 0;   ///< two-triangle edges walked the same way by both
  size_t degenerate_triangles = 0;///< repeated vertex or (near) zero area
  /// Divergence-theorem volume; holes are closed by a fan to each loop's
  /// centroid first, so an open scan still gets a sensible estimate.
  double signed_volume = 0;
  double surface_area = 0;
  std::optional<int> genus;       ///< total genus; only for closed, manifold meshes
  /// The winding number along a grid of rays; only for closed meshes whose
  /// every edge is walked as often each way (edges_balanced). Says whether
  /// parts overlap and the union's volume.
  std::optional<WindingSweep> winding;

  bool watertight() const { return boundary_edges == 0 && non_manifold_edges == 0; }
  bool inside_out() const { return signed_volume < 0; }
  /// Some region is enclosed twice: intersecting or nested parts, or a
  /// surface that passes through itself.
  bool overlapping() const { return winding && winding->overlapping(); }
  /// The solid's volume: where parts overlap, the union's (from the winding
  /// sweep), not the sum of the parts'.
  double volume() const {
    if (overlapping()) return winding->volume;
    return signed_volume < 0 ? -signed_volume : signed_volume;
  }
};

MeshDiagnostics diagnose(const Mesh& mesh);

/// Each triangle's connected component (triangles joined through shared
/// vertices, the count MeshDiagnostics::components gives), numbered from 0
/// in the order of each component's first triangle.
std::vector<uint32_t> triangle_components(const Mesh& mesh);

}  // namespace pfill
