/// @file sdf.hpp
/// @brief The signed distance field of a mesh on a regular grid: what the
/// boundary kernel samples in the fill, built here from Boundary queries;
/// plus trilinear sampling and its gradient on the host.
///
/// Values are negative inside. Grid samples within the band of the surface
/// (`band` inside the solid, `outer_band` outside it) hold the exact
/// distance (as float); farther samples hold a cheap value of the right
/// sign whose magnitude is at least that side's band and within one coarse
/// cell diagonal of the truth (trilinear interpolation of exact values on a
/// coarser level). Trilinear values take their extremes at the corners, so
/// the deepest grid point of a deep region is one of those exact corners.
/// The fill asks for exact values only a little deeper than where the wall
/// acts (a radius), and a thinner band outside, where only the sign and the
/// direction back in matter (fill_plan.cpp).
/// The build refines an octree of grid cells top-down: a cell whose corner
/// distances prove it lies wholly farther than its side's band from the
/// surface (1-Lipschitz bound) is filled by interpolation, every other cell
/// is split until single grid cells, whose corners get exact values (except
/// corners that the parent's corners already prove to lie outside the band:
/// those are interpolated too). Exact work is thus ~1.2x the number of grid
/// points within the band.
/// Signs: ray-parity majority vote on the coarsest level (robust to small
/// holes), the closest feature's pseudonormal below it where the mesh is
/// closed (Boundary::fast_signed_distance), and a whole deep cell shares
/// the sign of its corners.
#pragma once
#include <array>
#include <cstddef>
#include <functional>

#include "pfill/boundary.hpp"
#include "pfill/grid.hpp"

namespace pfill {

struct SdfOptions {
  SdfOptions() = default;
  explicit SdfOptions(double spacing_) : spacing(spacing_) {}

  double spacing = 0;    ///< grid spacing, > 0
  double margin = -1;    ///< added to every side of the bounding box; < 0: 3 spacings
  double band = -1;      ///< exact where |distance| < band; < 0: 4 spacings; infinity: exact everywhere
  double outer_band = -1;  ///< outside the solid, exact where distance < outer_band; < 0: the same as band
  /// Inside, deeper than the band: exact values on a lattice of at most this
  /// many spacings (rounded down to a power of two), the rest interpolated
  /// from it, so the deepest point is found within about a cell of this
  /// size; 0: as coarse as the octree allows (up to ~1/8 of the box).
  int inside_cell = 0;
  size_t max_samples = size_t(1) << 31;  ///< refuse larger grids (2^31 floats = 8 GiB)
  /// Called from the building thread with the fraction done (0..1); may be empty.
  std::function<void(double)> progress;
};

struct SdfStats {
  std::array<int, 3> dims{0, 0, 0};
  size_t samples = 0;        ///< grid points
  size_t triangles = 0;
  size_t bytes = 0;          ///< memory of the field (the values array)
  size_t scratch_bytes = 0;  ///< peak extra memory while building
  double seconds = 0;        ///< wall-clock build time
  size_t exact_queries = 0;  ///< grid points given an exact distance
  size_t parity_queries = 0; ///< grid points whose sign needed a ray vote
  double band = 0;        ///< inside the solid
  double outer_band = 0;  ///< outside it
  int levels = 0;            ///< octree levels above the grid
};

/// Spacing that gives `samples_on_longest_axis` grid points along the longest
/// side of `bounds` grown by `margin_spacings` spacings on each side.
double spacing_for_resolution(const Box3& bounds, int samples_on_longest_axis, double margin_spacings = 3);

/// The grid build_signed_distance_field lays over `bounds` (origin,
/// spacing, dims; no values): the bounds plus the margin, centred. Throws
/// pfill::Error on a bad spacing or margin, or a grid over max_samples.
ScalarGrid sdf_lattice(const Box3& bounds, const SdfOptions& options);

/// Builds the field of `boundary`'s mesh over its bounding box plus the
/// margin, centred; parallel (TBB). Throws pfill::Error on a bad spacing,
/// margin or band, or a grid over max_samples.
ScalarGrid build_signed_distance_field(const Boundary& boundary, const SdfOptions& options,
                                       SdfStats* stats = nullptr);

/// Trilinear value at p. Outside the grid: the value at the nearest grid
/// point of the box plus the distance to it (outside the grid is outside the
/// mesh, and the value keeps growing away from it).
double sample(const ScalarGrid& grid, const Vec3& p);

/// Gradient of sample(): the analytic gradient of the trilinear interpolant
/// of p's cell (continuous inside a cell; on a cell face, the upper cell's).
Vec3 gradient(const ScalarGrid& grid, const Vec3& p);

}  // namespace pfill
