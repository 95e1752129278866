// The field's samples computed from the mesh on demand: see exact_field.hpp.
#include "pfill/exact_field.hpp"

#include <algorithm>

namespace pfill {

double ExactField::at(int i, int j, int k) const {
  const std::array<int, 3>& d = lattice_.dims;
  return at(lattice_.point(std::clamp(i, 0, d[0] - 1), std::clamp(j, 0, d[1] - 1), std::clamp(k, 0, d[2] - 1)));
}

}  // namespace pfill
