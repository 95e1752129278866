// The cells a sphere can reach (see reachable_cells.hpp).
#include "engine/reachable_cells.hpp"

#include <algorithm>
#include <cmath>

namespace pfill {
namespace {

// The cell along one axis of each sample along it.
std::vector<int> cell_of_samples(double field_origin, double spacing, int samples, double origin, double cell_size,
                                 int cells) {
  std::vector<int> out(static_cast<size_t>(samples));
  for (int i = 0; i < samples; ++i) {
    const double c = std::floor((field_origin + i * spacing - origin) / cell_size);
    out[static_cast<size_t>(i)] = static_cast<int>(std::clamp(c, 0.0, static_cast<double>(cells - 1)));
  }
  return out;
}

// `marked` grown by one cell in every direction (26 neighbours), one axis at a time.
std::vector<uint8_t> dilated(std::vector<uint8_t> marked, const int dims[3]) {
  const size_t stride[3] = {1, static_cast<size_t>(dims[0]), static_cast<size_t>(dims[0]) * dims[1]};
  for (int a = 0; a < 3; ++a) {
    std::vector<uint8_t> out = marked;
    for (size_t cell = 0; cell < marked.size(); ++cell) {
      if (!marked[cell]) continue;
      const int along = static_cast<int>((cell / stride[a]) % static_cast<size_t>(dims[a]));
      if (along > 0) out[cell - stride[a]] = 1;
      if (along + 1 < dims[a]) out[cell + stride[a]] = 1;
    }
    marked = std::move(out);
  }
  return marked;
}

}  // namespace

std::vector<uint8_t> reachable_cells(const ScalarGrid& field, const Vec3& origin, double cell_size,
                                     const int dims[3]) {
  const size_t cells = static_cast<size_t>(dims[0]) * dims[1] * dims[2];
  std::vector<uint8_t> marked(cells, 0);
  const std::vector<int> cx = cell_of_samples(field.origin.x, field.spacing, field.dims[0], origin.x, cell_size, dims[0]);
  const std::vector<int> cy = cell_of_samples(field.origin.y, field.spacing, field.dims[1], origin.y, cell_size, dims[1]);
  const std::vector<int> cz = cell_of_samples(field.origin.z, field.spacing, field.dims[2], origin.z, cell_size, dims[2]);
  // Samples farther out than the field's outer band hold at least the band,
  // not the distance, so "closer than a cell" is judged only up to the band;
  // the dilation by a cell makes up for it.
  const float near = static_cast<float>(cell_size);
  const float* v = field.values.data();
  for (int k = 0; k < field.dims[2]; ++k)
    for (int j = 0; j < field.dims[1]; ++j) {
      uint8_t* row = marked.data() + static_cast<size_t>(dims[0]) * (cy[j] + static_cast<size_t>(dims[1]) * cz[k]);
      for (int i = 0; i < field.dims[0]; ++i, ++v)
        if (*v < near) row[cx[i]] = 1;
    }
  return dilated(std::move(marked), dims);
}

}  // namespace pfill
