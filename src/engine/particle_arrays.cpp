// The particles' device arrays (see particle_arrays.hpp).
#include "engine/particle_arrays.hpp"

namespace pfill {

ParticleArrays::ParticleArrays(Device& device)
    : X{{device, "positions"}, {device, "positions"}},
      V{{device, "velocities"}, {device, "velocities"}},
      flags(device, "flags"),
      clearance(device, "wall clearance"),
      kept_cell(device, "wall kept cells"),
      kept_corners(device, "wall kept corners") {}

void ParticleArrays::grow(size_t cap, int copies) {
  const size_t n = ids.size();
  for (int h = 0; h < 2; ++h) {
    // only the current copy holds particles; the other is written before it is read
    const size_t keep = h == cur ? n : 0;
    if (h < copies) {
      X[h].grow(cap, keep, true);
      V[h].grow(cap, keep, true);
    }
  }
  flags.grow(cap, n);
  clearance.grow(cap, n);
  // An entry holds its cell's corners whichever particle wrote it: those
  // kept stay true, the new memory holds none.
  kept_cell.grow(cap, n);
  if (cap > n) kept_cell.fill(kNoCell, n);
  kept_corners.grow(cap, (n + 7) / 8 * 8, true);  // (by octets: the last one's lanes past n too)
  copies_ = copies;
}

void ParticleArrays::write(size_t first, const std::vector<cl_float4>& xs, const std::vector<cl_float4>& vs) {
  X[cur].write(first, xs);
  V[cur].write(first, vs);
  flags.write(first, std::vector<cl_uint>(xs.size(), 0));
  clearance.write(first, std::vector<cl_float>(xs.size(), 0.0f));
}

void ParticleArrays::write_velocities(size_t first, const std::vector<cl_float4>& vs) { V[cur].write(first, vs); }

void ParticleArrays::read(size_t count, std::vector<cl_float4>& xs, std::vector<cl_float4>& vs) const {
  X[cur].read(count, xs, false);
  V[cur].read(count, vs, true);
}

void ParticleArrays::permute(const std::vector<size_t>& order, const std::vector<cl_float4>& xs,
                             const std::vector<cl_float4>& vs) {
  const size_t n = order.size();
  const std::vector<cl_uint> f = flags.read(n);
  std::vector<cl_float4> xs2(n), vs2(n);
  std::vector<cl_uint> f2(n);
  std::vector<uint64_t> ids2 = ids;  // (an order of the first n only leaves the rest's ids)
  for (size_t k = 0; k < n; ++k) {
    const size_t i = order[k];
    xs2[k] = xs[i];
    vs2[k] = vs[i];
    f2[k] = f[i];
    ids2[k] = ids[i];
  }
  X[cur].write(0, xs2, false);
  V[cur].write(0, vs2, false);
  flags.write(0, f2, true);
  // Wall clearances are lower bounds, a cache: 0 makes the next step sample the field.
  if (n > 0) clearance.fill(0.0f, 0, n);
  ids = std::move(ids2);
}

std::vector<size_t> ParticleArrays::flagged(size_t count) const {
  const std::vector<cl_uint> f = flags.read(count);
  std::vector<size_t> out;
  for (size_t i = 0; i < count; ++i)
    if (f[i]) out.push_back(i);
  return out;
}

}  // namespace pfill
