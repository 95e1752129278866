// The field's samples computed from the mesh on demand: see exact_field.hpp.
#include "pfill/exact_field.hpp"

#include <algorithm>

namespace pfill {

double ExactField::at(int i, int j, int k, double bound) const {
  const std::array<int, 3>& d = lattice_.dims;
  const Vec3 p = lattice_.point(std::clamp(i, 0, d[0] - 1), std::clamp(j, 0, d[1] - 1), std::clamp(k, 0, d[2] - 1));
  return boundary_.fast_signed_distance(p, bound);
}

}  // namespace pfill
