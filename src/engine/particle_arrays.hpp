// The particles on the device: positions with radii (X) and velocities
// with inverse masses (V), in one copy or two (the GPU form's ping-pong),
// the outside flags, the wall clearances and kept cells, and host-side the
// caller's ids.
#pragma once
#include <CL/opencl.hpp>

#include <cstdint>
#include <vector>

#include "engine/device_array.hpp"

namespace pfill {

class ParticleArrays {
 public:
  explicit ParticleArrays(Device& device);

  /// Room for `cap` particles in `copies` (1 or 2) copies of X and V,
  /// the particles kept (zeroed past them: the CPU pair loop reads, then
  /// masks, particles a row only held once, which must be finite).
  void grow(size_t cap, int copies);
  /// Writes particles [first, first + xs.size()) (flags and clearances 0); blocking.
  void write(size_t first, const std::vector<cl_float4>& xs, const std::vector<cl_float4>& vs);
  /// Writes the velocities of particles [first, first + vs.size()) only; blocking.
  void write_velocities(size_t first, const std::vector<cl_float4>& vs);
  /// The current X and V of the first `count` particles (blocking).
  void read(size_t count, std::vector<cl_float4>& xs, std::vector<cl_float4>& vs) const;
  /// The particles reordered: new index k holds old order[k]; xs and vs
  /// are their current X and V (read(); moved in: permuted in place). An
  /// order of the first order.size() particles leaves the others as they
  /// are. Blocking.
  void permute(const std::vector<size_t>& order, std::vector<cl_float4> xs, std::vector<cl_float4> vs);
  /// Indices of the flagged particles among the first `count`.
  std::vector<size_t> flagged(size_t count) const;

  /// Every kept cell forgotten: the field changed.
  void forget_kept_cells() {
    if (kept_cell.size() > 0) kept_cell.fill(kNoCell);
  }

  size_t capacity() const { return flags.size(); }
  /// The current copy of X and V, and the one a ping-pong step writes.
  const DeviceArray<cl_float4>& x() const { return X[cur]; }
  const DeviceArray<cl_float4>& v() const { return V[cur]; }
  const DeviceArray<cl_float4>& x_next() const { return X[copies_ - 1 - cur]; }
  const DeviceArray<cl_float4>& v_next() const { return V[copies_ - 1 - cur]; }
  /// After a step: the copy it wrote is current.
  void swap() { cur = copies_ - 1 - cur; }

  DeviceArray<cl_float4> X[2], V[2];
  DeviceArray<cl_uint> flags;
  DeviceArray<cl_float> clearance;  // lower bounds on the distance to the wall (0: sample the field)
  /// The wall's kept cells (kernels/cpu_step.cl pf_field_sample8_kept): each
  /// index's last sampled cell (kNoCell: none) and its 8 corner values
  /// (by octets of particles: corner c of octet o's lanes at 8 o + c).
  DeviceArray<cl_uint> kept_cell;
  DeviceArray<cl_float8> kept_corners;
  static constexpr cl_uint kNoCell = 0xffffffffu;  // cpu_step.cl PF_NO_CELL
  std::vector<uint64_t> ids;        // Particle::id of each index, kept through removals and sorts
  int cur = 0;

 private:
  int copies_ = 1;
};

}  // namespace pfill
