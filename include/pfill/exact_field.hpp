/// @file exact_field.hpp
/// @brief The signed distance field's grid (as build_signed_distance_field
/// lays it out) without its values: each sample is computed from the mesh
/// when asked for, the same exact distance the whole field holds within its
/// band. For engines that read only the bricks near the wall their
/// particles reach (the LAMMPS engine, over MPI ranks): no process then
/// holds the whole field (docs/lammps_engine.md, "The wall's field per
/// rank").
#pragma once
#include <limits>

#include "pfill/boundary.hpp"
#include "pfill/grid.hpp"
#include "pfill/sdf.hpp"

namespace pfill {

class ExactField {
 public:
  /// The grid of build_signed_distance_field(boundary, options);
  /// `boundary` must outlive this. Throws pfill::Error as sdf_lattice does.
  ExactField(const Boundary& boundary, const SdfOptions& options)
      : boundary_(boundary), lattice_(sdf_lattice(boundary.mesh().bounds(), options)) {}

  /// Origin, spacing and dims; no values.
  const ScalarGrid& lattice() const { return lattice_; }
  /// The signed distance at grid point (i, j, k), each clamped into the
  /// grid: negative inside, computed as the whole field's exact samples are
  /// (Boundary::fast_signed_distance); `bound`, a bound on its magnitude
  /// known to the caller, narrows the search. Thread-safe.
  double at(int i, int j, int k, double bound = std::numeric_limits<double>::infinity()) const;
  /// The signed distance at p. Thread-safe.
  double at(const Vec3& p) const { return boundary_.fast_signed_distance(p); }

 private:
  const Boundary& boundary_;
  ScalarGrid lattice_;
};

}  // namespace pfill
