/// @file shapes.hpp
/// @brief Closed (and deliberately broken) triangle meshes generated in
/// code: the built-in shapes of `pfill` and the fixtures of the test suite,
/// which must not need any file.
#pragma once
#include <string>
#include <vector>

#include "pfill/mesh.hpp"

namespace pfill {

/// Icosahedron subdivided `subdivisions` times, vertices on the sphere of
/// `radius` about the origin; outward oriented, 20 * 4^s triangles.
Mesh make_icosphere(double radius = 1.0, int subdivisions = 3);

/// Axis-aligned cube [-h, h]^3, each face split into n x n quads (2 triangles
/// each); outward oriented. Corner UVs run 0..1 across every face.
Mesh make_cube(double half_size = 1.0, int n = 1);

/// Torus about the z axis: ring radius R, tube radius r, `nu` segments around
/// the ring and `nv` around the tube; genus 1, outward oriented.
Mesh make_torus(double ring_radius = 1.0, double tube_radius = 0.4, int nu = 48, int nv = 24);

/// make_cube with the +z face removed: an open mesh with 4*n boundary edges.
Mesh make_open_cube(double half_size = 1.0, int n = 1);

/// make_cube with every triangle's winding reversed: negative signed volume.
Mesh make_inside_out_cube(double half_size = 1.0, int n = 1);

/// The names accepted by make_builtin ("sphere", "cube", "torus").
std::vector<std::string> builtin_shape_names();

/// A built-in shape by name, at a size that suits a demo fill; throws
/// pfill::Error listing the names when `name` is unknown.
Mesh make_builtin(const std::string& name);

}  // namespace pfill
