// kernels/physics.cl instantiated in double precision for host C++: the
// C++ reference engine (src/engine/reference.cpp) and the LAMMPS engine's
// step callback (src/lammps/) compute with these, so both run the kernels'
// formulas word for word. Everything is in pfill::physics: the pf_* rules
// of physics.cl, `sample` (the signed distance field's trilinear value and
// gradient at a point, as the kernels read it) and `wall_push` (physics.cl's
// push and reflection over that sampler).
//
// It lives beside physics.cl rather than under include/pfill/ because it
// includes that file by a relative path: the layers' public headers are
// links in the build tree (cmake/pfill_layers.cmake), from where
// kernels/ cannot be reached, and include/pfill/ is installed, kernels/ is
// not. Host code reaches it as "../../kernels/physics_double.hpp", as it
// reached physics.cl before. Not a kernel: the library embeds kernels/*.cl
// only.
#pragma once

#include <cmath>
#include <math.h>

#include "pfill/engine/params.hpp"  // kWallIterations
#include "pfill/grid.hpp"

namespace pfill {
namespace physics {

// What physics.cl needs from OpenCL C, in double precision.
using uint = unsigned int;
inline int min(int a, int b) { return a < b ? a : b; }
template <class T>
inline T select(T a, T b, int c) {
  return c ? b : a;
}
using ::floor;
using ::fma;
using ::fmax;
using ::fmin;
using ::pow;
using ::sqrt;
#define PF_REAL double
#define PF_FN inline
#define PF_GLOBAL
#include "physics.cl"
#undef PF_REAL
#undef PF_FN
#undef PF_GLOBAL

/// The field's value at (x, y, z) and its gradient into g (physics.cl's
/// trilinear sampler, as the kernels read the field).
inline double sample(const ScalarGrid& f, double x, double y, double z, double* g) {
  return pf_sdf_sample(f.values.data(), f.dims[0], f.dims[1], f.dims[2], f.origin.x, f.origin.y, f.origin.z,
                       1 / f.spacing, x, y, z, g);
}

// physics.cl's wall push and reflection, over `sample`.
#define PF_FN inline
#define PF_WALL_ITERATIONS kWallIterations
#define PF_SAMPLE_DOUBLE(PX, PY, PZ, G, LANES) sample(field, PX, PY, PZ, G)
PF_DEFINE_WALL_PUSH(wall_push, double, int, PF_ANY1, PF_SAMPLE_DOUBLE, pf_wall_velocity_change,
                    const ScalarGrid& field)
#undef PF_SAMPLE_DOUBLE
#undef PF_WALL_ITERATIONS
#undef PF_FN

}  // namespace physics
}  // namespace pfill
