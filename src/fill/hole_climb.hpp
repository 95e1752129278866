// The climb every hole search ends with: from a grid point, to where the
// nearest sphere is farthest (a local maximum of the gap), within the
// points a sphere may take.
#pragma once
#include "pfill/vec3.hpp"

namespace pfill {

/// Moves `p` uphill on `gap` along the 14 directions of a cube's faces and
/// corners, in steps from `first_step` halving down to `last_step`, taking
/// only points where `allowed` holds; returns the gap reached.
template <class Gap, class Allowed>
double climb_to_hole_centre(Vec3& p, double first_step, double last_step, const Gap& gap, const Allowed& allowed) {
  static const Vec3 dirs[] = {{1, 0, 0},  {-1, 0, 0},  {0, 1, 0},   {0, -1, 0},  {0, 0, 1},
                              {0, 0, -1}, {1, 1, 1},   {1, 1, -1},  {1, -1, 1},  {1, -1, -1},
                              {-1, 1, 1}, {-1, 1, -1}, {-1, -1, 1}, {-1, -1, -1}};
  double g = gap(p);
  for (double step = first_step; step > last_step;) {
    bool moved = false;
    for (const Vec3& dir : dirs) {
      const Vec3 q = p + dir * (step / length(dir));
      const double gq = gap(q);
      if (gq > g && allowed(q)) {
        p = q;
        g = gq;
        moved = true;
      }
    }
    if (!moved) step *= 0.5;
  }
  return g;
}

}  // namespace pfill
