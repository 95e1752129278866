/* engine.cl: the particle update as OpenCL C 1.2 kernels. Built after
 * physics.cl (its functions) with a prelude of #defines (the constants
 * below; src/engine/engine.cpp writes them). The defaults here only let the
 * two files compile without the prelude.
 *
 * State (float4 per particle): X = (position, radius), V = (velocity at the
 * half step, 1 / mass). One step is ONE launch of `advance`: it reads X, V and
 * the cell list built for X, and writes X', V' and the cell list for X'
 * into the other halves of ping-pong buffers, so no kernel reads what
 * another work-item writes. Leapfrog (velocity Verlet written with half-step
 * velocities): u(t+1/2) = u(t-1/2) + dt F(x(t), u(t-1/2))/m, F the pair
 * forces plus the contact dashpots,
 * x(t+1) = x(t) + dt u(t+1/2), then the wall.
 *
 * Cells: a uniform grid, at most PF_CELL_CAP particles a cell. A cell's
 * count word is (stamp << 8 | count); a count whose stamp is not the
 * current one reads as zero, so cells never need clearing.
 *
 * Per-step scalars: every work-group reduces its particles into a partial
 * record; group 0 of the next step (or finalize_history) reduces the
 * previous step's partials into one HISTORY record of 8 words:
 * kinetic energy, max speed, max displacement, 0, then as uints: colliding
 * pairs, flagged particles, cells over capacity, particle count. */
#ifndef PF_SIGMA2
#define PF_SIGMA2 1.0f
#define PF_EPS 1.0f
#define PF_EXP_A 12.0f
#define PF_EXP_B 6.0f
#define PF_EXP_A_HALF 6
#define PF_EXP_B_HALF 3
#define PF_RC2 1.2599210f
#define PF_FORCE_CAP 100.0f
#define PF_D_MIN 0.001f
#define PF_DASHPOT 3.6f
#define PF_CONTACT2 1.0f
#define PF_WALL_RESTITUTION 0.5f
#define PF_DT 0.005f
#define PF_DAMP 1.0f
#define PF_VMAX 10.0f
#define PF_CELL_CAP 16u
#define PF_WALL_ITERATIONS 2
#endif

#define PF_COUNT_MASK 0xFFu
#define PF_RECORD 8

/* Cell coordinates of a point, clamped into the grid (a particle outside
 * keeps its neighbours: they clamp to the same or an adjacent cell). */
int4 pf_cell_of(float4 x, float4 origin, float4 inv_size, int4 dims) {
  const int4 c = convert_int4_rtn((x - origin) * inv_size);
  return clamp(c, (int4)(0), dims - (int4)(1));
}

uint pf_cell_index(int4 c, int4 dims) { return (uint)(c.x + dims.x * (c.y + dims.y * c.z)); }

/* Number of particles listed in a cell under `stamp` (may exceed the cap). */
uint pf_cell_count(__global const uint* counts, uint cell, uint stamp) {
  const uint raw = counts[cell];
  return (raw >> 8) == stamp ? (raw & PF_COUNT_MASK) : 0u;
}

/* Adds particle i to a cell under `stamp`; a stale count restarts at zero. */
void pf_cell_insert(__global uint* counts, __global uint* slots, uint cell, uint stamp, uint i) {
  uint old = atomic_or(&counts[cell], 0u);
  for (;;) {
    const uint count = (old >> 8) == stamp ? (old & PF_COUNT_MASK) : 0u;
    const uint want = (stamp << 8) | min(count + 1u, PF_COUNT_MASK);
    const uint seen = atomic_cmpxchg(&counts[cell], old, want);
    if (seen == old) {
      if (count < PF_CELL_CAP) slots[cell * PF_CELL_CAP + count] = i;
      return;
    }
    old = seen;
  }
}

/* Tree reduction of a work-group: x, w summed, y, z maxima of lf; x, y, z
 * summed, w maximum of lu. The result is in element 0. Work-group size must
 * be a power of two. */
void pf_group_reduce(__local float4* lf, __local uint4* lu) {
  const uint lid = get_local_id(0);
  for (uint s = get_local_size(0) / 2; s > 0; s >>= 1) {
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid < s) {
      const float4 a = lf[lid], b = lf[lid + s];
      lf[lid] = (float4)(a.x + b.x, fmax(a.y, b.y), fmax(a.z, b.z), a.w + b.w);
      const uint4 p = lu[lid], q = lu[lid + s];
      lu[lid] = (uint4)(p.x + q.x, p.y + q.y, p.z + q.z, max(p.w, q.w));
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
}

/* Reduces `groups` partial records into history[slot]; all items of one group call it. */
void pf_partials_to_history(__global const float* partials, uint groups, __global float* history, uint slot,
                            __local float4* lf, __local uint4* lu) {
  const uint lid = get_local_id(0);
  float4 f = (float4)(0.0f);
  uint4 u = (uint4)(0u);
  for (uint g = lid; g < groups; g += get_local_size(0)) {
    const float4 pf = vload4(0, partials + g * PF_RECORD);
    const uint4 pu = as_uint4(vload4(1, partials + g * PF_RECORD));
    f = (float4)(f.x + pf.x, fmax(f.y, pf.y), fmax(f.z, pf.z), 0.0f);
    u = (uint4)(u.x + pu.x, u.y + pu.y, u.z + pu.z, max(u.w, pu.w));
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  lf[lid] = f;
  lu[lid] = u;
  pf_group_reduce(lf, lu);
  if (lid == 0) {
    vstore4(lf[0], 0, history + slot * PF_RECORD);
    vstore4(as_float4(lu[0]), 1, history + slot * PF_RECORD);
  }
}

/* Inserts particles [first, first + count) of X into the cells under `stamp`. */
__kernel void insert_cells(__global const float4* X, __global uint* counts, __global uint* slots, const uint stamp,
                           const float4 cell_origin, const float4 cell_inv, const int4 cell_dims, const uint first,
                           const uint count) {
  const uint k = get_global_id(0);
  if (k >= count) return;
  const uint i = first + k;
  pf_cell_insert(counts, slots, pf_cell_index(pf_cell_of(X[i], cell_origin, cell_inv, cell_dims), cell_dims), stamp, i);
}

/* One birth: writes particle `index` and lists it in the current cells. */
__kernel void birth_one(__global float4* X, __global float4* V, __global uint* flags, __global uint* counts,
                        __global uint* slots, const uint stamp, const float4 cell_origin, const float4 cell_inv,
                        const int4 cell_dims, const uint index, const float4 x, const float4 v) {
  if (get_global_id(0) != 0) return;
  X[index] = x;
  V[index] = v;
  flags[index] = 0u;
  if (stamp != 0u) pf_cell_insert(counts, slots, pf_cell_index(pf_cell_of(x, cell_origin, cell_inv, cell_dims), cell_dims), stamp, index);
}

/* One removal: particle `from` (the last) takes the place of `to`. */
__kernel void move_particle(__global float4* X, __global float4* V, __global uint* flags, const uint from,
                            const uint to) {
  if (get_global_id(0) != 0) return;
  X[to] = X[from];
  V[to] = V[from];
  flags[to] = flags[from];
}

/* Reduces the last step's partial records into its history slot. */
__kernel void finalize_history(__global const float* partials, const uint groups, __global float* history,
                               const uint slot, __local float4* lf, __local uint4* lu) {
  pf_partials_to_history(partials, groups, history, slot, lf, lu);
}

/* For tests: the indices of each particle's neighbours (pairs the step
 * considers: d^2 < max(rc^2, (r_i + r_j)^2)), at most max_out each. */
__kernel void list_neighbours(__global const float4* X, __global const uint* counts, __global const uint* slots,
                              const uint stamp, const float4 cell_origin, const float4 cell_inv, const int4 cell_dims,
                              const uint n, __global uint* out_count, __global uint* out, const uint max_out) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const float4 xi = X[i];
  const int4 c = pf_cell_of(xi, cell_origin, cell_inv, cell_dims);
  uint found = 0;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int4 cc = c + (int4)(dx, dy, dz, 0);
        if (any(cc.xyz < (int3)(0)) || any(cc.xyz >= cell_dims.xyz)) continue;
        const uint cell = pf_cell_index(cc, cell_dims);
        const uint m = min(pf_cell_count(counts, cell, stamp), PF_CELL_CAP);
        for (uint k = 0; k < m; ++k) {
          const uint j = slots[cell * PF_CELL_CAP + k];
          if (j == i) continue;
          const float4 xj = X[j];
          float4 d = xi - xj;
          d.w = 0.0f;
          const float rs = xi.w + xj.w;
          if (dot(d, d) < fmax(PF_RC2, rs * rs)) {
            if (found < max_out) out[i * max_out + found] = j;
            ++found;
          }
        }
      }
  out_count[i] = found;
}

/* The whole update of one particle (see the top of the file). walls.w != 0
 * when a field is set: sdf_origin = (origin, 1/spacing), sdf_dims = (nx, ny, nz, has_walls). */
__kernel void advance(__global const float4* X, __global const float4* V, __global float4* X_out, __global float4* V_out,
                   __global const uint* counts, __global const uint* slots, const uint stamp,
                   __global uint* counts_out, __global uint* slots_out, const uint stamp_out,
                   const float4 cell_origin, const float4 cell_inv, const int4 cell_dims,
                   __global const float* sdf, const float4 sdf_origin, const int4 sdf_dims,
                   __global uint* flags, const uint n,
                   __global float* partials, __global const float* prev_partials, const uint prev_groups,
                   __global float* history, const uint prev_slot,
                   __local float4* lf, __local uint4* lu) {
  const uint i = get_global_id(0);
  float4 red_f = (float4)(0.0f);  /* kinetic energy, speed, displacement, 0 */
  uint4 red_u = (uint4)(0u, 0u, 0u, n);  /* colliding pairs, flagged, overflow, count */
  if (i < n) {
    const float4 xi = X[i];
    const float4 vi = V[i];
    const float ri = xi.w, inv_mi = vi.w;
    float4 force = (float4)(0.0f);
    const int4 c = pf_cell_of(xi, cell_origin, cell_inv, cell_dims);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int4 cc = c + (int4)(dx, dy, dz, 0);
          if (any(cc.xyz < (int3)(0)) || any(cc.xyz >= cell_dims.xyz)) continue;
          const uint cell = pf_cell_index(cc, cell_dims);
          uint m = pf_cell_count(counts, cell, stamp);
          if (m > PF_CELL_CAP) {
            red_u.z = 1u;
            m = PF_CELL_CAP;
          }
          __global const uint* list = slots + cell * PF_CELL_CAP;
          for (uint k = 0; k < m; ++k) {
            const uint j = list[k];
            if (j == i) continue;
            const float4 xj = X[j];
            float4 d = xi - xj;
            d.w = 0.0f;
            float d2 = dot(d, d);
            const float rs = ri + xj.w;
            if (d2 >= fmax(PF_RC2, rs * rs)) continue;
            if (d2 < PF_D_MIN * PF_D_MIN) { /* on top of each other: a fixed, antisymmetric direction */
              d = (float4)(i < j ? -PF_D_MIN : PF_D_MIN, 0.0f, 0.0f, 0.0f);
              d2 = PF_D_MIN * PF_D_MIN;
            }
            force += pf_lj_force_scale(d2, PF_SIGMA2, PF_EPS, PF_EXP_A, PF_EXP_B, PF_EXP_A_HALF, PF_EXP_B_HALF,
                                       PF_RC2, PF_FORCE_CAP) * d;
            if (d2 < fmax(rs * rs, PF_CONTACT2)) {
              const float4 vj = V[j];
              const float4 nrm = d * rsqrt(d2);
              float4 du = vi - vj;
              du.w = 0.0f;
              force += pf_contact_damping(dot(du, nrm), inv_mi, vj.w, PF_DASHPOT) * nrm;
              red_u.x += (j > i && d2 < rs * rs) ? 1u : 0u;
            }
          }
        }
    float4 u = vi;
    u.w = 0.0f;
    u = (u + (PF_DT * inv_mi) * force) * PF_DAMP;
    const float speed = length(u);
    if (speed > PF_VMAX) u *= PF_VMAX / speed; /* displacement cap: at most PF_VMAX dt a step */
    float4 xn = xi + PF_DT * u;
    xn.w = ri;
    if (sdf_dims.w != 0) {
      float g[3];
      float phi = pf_sdf_sample(sdf, sdf_dims.x, sdf_dims.y, sdf_dims.z, sdf_origin.x, sdf_origin.y, sdf_origin.z,
                                sdf_origin.w, xn.x, xn.y, xn.z, g);
      const float4 grid_pos = (xn - sdf_origin) * sdf_origin.w;
      const int outside_box = grid_pos.x < 0.0f || grid_pos.y < 0.0f || grid_pos.z < 0.0f ||
                              grid_pos.x > (float)(sdf_dims.x - 1) || grid_pos.y > (float)(sdf_dims.y - 1) ||
                              grid_pos.z > (float)(sdf_dims.z - 1);
      const uint flagged = (phi > 0.0f || outside_box) ? 1u : 0u;
      red_u.y = flagged;
      if (flagged) flags[i] = 1u;
      if (phi > -ri) {
        for (int it = 0; it < PF_WALL_ITERATIONS && phi > -ri; ++it) {
          const float gl = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
          if (!(gl > 1e-20f)) break;
          const float push = (phi + ri) / gl;
          xn.x -= push * g[0];
          xn.y -= push * g[1];
          xn.z -= push * g[2];
          phi = pf_sdf_sample(sdf, sdf_dims.x, sdf_dims.y, sdf_dims.z, sdf_origin.x, sdf_origin.y, sdf_origin.z,
                              sdf_origin.w, xn.x, xn.y, xn.z, g);
        }
        const float gl = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
        if (gl > 1e-20f) {
          const float4 nrm = (float4)(g[0], g[1], g[2], 0.0f) / gl;
          u += pf_wall_velocity_change(dot(u, nrm), PF_WALL_RESTITUTION) * nrm;
        }
      }
    }
    X_out[i] = xn;
    V_out[i] = (float4)(u.x, u.y, u.z, inv_mi);
    pf_cell_insert(counts_out, slots_out, pf_cell_index(pf_cell_of(xn, cell_origin, cell_inv, cell_dims), cell_dims),
                   stamp_out, i);
    float4 dxn = xn - xi;
    dxn.w = 0.0f;
    red_f = (float4)(0.5f * dot(u, u) / inv_mi, length(u), length(dxn), 0.0f);
  }
  const uint lid = get_local_id(0);
  lf[lid] = red_f;
  lu[lid] = red_u;
  pf_group_reduce(lf, lu);
  if (lid == 0) {
    vstore4(lf[0], 0, partials + get_group_id(0) * PF_RECORD);
    vstore4(as_float4(lu[0]), 1, partials + get_group_id(0) * PF_RECORD);
  }
  if (get_group_id(0) == 0 && prev_groups > 0) pf_partials_to_history(prev_partials, prev_groups, history, prev_slot, lf, lu);
}
