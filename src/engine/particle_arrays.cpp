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

namespace {

// v[k] becomes v[order[k]] for k < order.size(), in place, cycle by cycle
// (copies of the state cost 48 MB at 1e6, on top of the engine's).
template <typename T>
void permute_in_place(std::vector<T>& v, const std::vector<size_t>& order, std::vector<bool>& done) {
  done.assign(order.size(), false);
  for (size_t start = 0; start < order.size(); ++start) {
    if (done[start]) continue;
    const T first = v[start];
    size_t k = start;
    for (; order[k] != start; k = order[k]) {
      v[k] = v[order[k]];
      done[k] = true;
    }
    v[k] = first;
    done[k] = true;
  }
}

}  // namespace

void ParticleArrays::permute(const std::vector<size_t>& order, std::vector<cl_float4> xs, std::vector<cl_float4> vs) {
  const size_t n = order.size();
  std::vector<cl_uint> f = flags.read(n);
  std::vector<bool> done;
  permute_in_place(xs, order, done);
  permute_in_place(vs, order, done);
  permute_in_place(f, order, done);
  permute_in_place(ids, order, done);  // (an order of the first n only leaves the rest's ids)
  X[cur].write(0, xs, false);
  V[cur].write(0, vs, false);
  flags.write(0, f, true);
  // Wall clearances are lower bounds, a cache: 0 makes the next step sample the field.
  if (n > 0) clearance.fill(0.0f, 0, n);
}

std::vector<size_t> ParticleArrays::flagged(size_t count) const {
  const std::vector<cl_uint> f = flags.read(count);
  std::vector<size_t> out;
  for (size_t i = 0; i < count; ++i)
    if (f[i]) out.push_back(i);
  return out;
}

}  // namespace pfill
