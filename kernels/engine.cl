/* engine.cl: the particle update as OpenCL C 1.2 kernels. Built after
 * physics.cl (its functions) with a prelude of #defines (the constants
 * below; src/engine/engine.cpp writes them). The defaults here only let the
 * two files compile without the prelude.
 *
 * State (float4 per particle): X = (position, radius), V = (velocity at the
 * half step, 1 / mass). The update is ONE launch of `advance`: it reads X
 * and V and writes X' and V', the other halves of ping-pong buffers, so no
 * work-item reads what another writes. Leapfrog (velocity Verlet written
 * with half-step velocities): u(t+1/2) = u(t-1/2) + dt F(x(t), u(t-1/2))/m,
 * F the pair forces plus the contact dashpots, x(t+1) = x(t) + dt u(t+1/2),
 * then the wall.
 *
 * Cells: a uniform grid, at most PF_CELL_CAP particles a cell. A cell's
 * count word is (stamp << 8 | count); a count whose stamp is not the
 * current one reads as zero, so cells never need clearing. A cell's slots
 * are one block of PF_CELL_CAP / 8 chunks, each of 5 rows of 8 floats
 * holding copies of 8 particles' x, y, z, radius and index (as uint bits),
 * so a list build reads 8 candidates at once as float8 vectors from 160
 * contiguous bytes, without gathers.
 *
 * Neighbour lists (Verlet, with a skin): each particle keeps the indices
 * of the particles within PF_RL of it (cutoff or contact reach, plus the
 * skin) when the list was built, and where it was (XREF). A step that moves
 * any particle more than half the skin from XREF raises a request flag; the
 * next step then fills the cells (insert_cells, which returns at once
 * otherwise) and rebuilds every list from them (each work-item its own
 * list). Flags rotate over three words: a step reads one, raises the next,
 * clears the third. Births and removals while the lists are valid update
 * them in place (birth_linked, remove_linked); bulk additions and growth
 * force a rebuild. A step is therefore two launches, the first nearly empty.
 *
 * The pair loop takes 8 list entries at a time as float8 vectors (PoCL
 * turns them into SIMD; GPUs run them as unrolled scalar code).
 *
 * Per-step scalars, with no barrier and no launch of their own: step t
 * writes one record per particle (S); during
 * step t+1, work-item k sums chunk k of step t's records into a partial (P);
 * during step t+2, work-item 0 sums those partials into the HISTORY record
 * of step t: 8 words, kinetic energy, max speed, max displacement, 0, then
 * as uints: colliding pairs, flagged particles, cell-overflow hits, particle
 * count. finalize_history finishes the (at most two) steps still in flight.
 *
 * Wall clearance: C[i] is a lower bound on how far particle i's sphere is
 * from the wall; it shrinks by 2 |dx| a step (the trilinear field changes
 * by at most sqrt(3) |dx|) and the field is sampled only when it reaches 0. */
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
#define PF_RL2 1.6f
#define PF_HALF_SKIN2 0.01f
#define PF_LIST_CAP 32u
#endif

#define PF_COUNT_MASK 0xFFu
#define PF_BLOCK (5u * PF_CELL_CAP) /* floats per cell in the slots buffer */
#define PF_SLOT(s, row) (((s) >> 3) * 40u + (row) * 8u + ((s) & 7u)) /* float of slot s, row 0-4, in a block */
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
void pf_cell_insert(__global uint* counts, __global float* slots, uint cell, uint stamp, uint i, float4 x) {
  uint old = atomic_or(&counts[cell], 0u);
  for (;;) {
    const uint count = (old >> 8) == stamp ? (old & PF_COUNT_MASK) : 0u;
    const uint want = (stamp << 8) | min(count + 1u, PF_COUNT_MASK);
    const uint seen = atomic_cmpxchg(&counts[cell], old, want);
    if (seen == old) {
      if (count < PF_CELL_CAP) {
        __global float* block = slots + cell * PF_BLOCK;
        block[PF_SLOT(count, 0u)] = x.x;
        block[PF_SLOT(count, 1u)] = x.y;
        block[PF_SLOT(count, 2u)] = x.z;
        block[PF_SLOT(count, 3u)] = x.w;
        block[PF_SLOT(count, 4u)] = as_float(i);
      }
      return;
    }
    old = seen;
  }
}

/* Per-particle record: (kinetic energy, speed, displacement, packed
 * counters: pairs in bits 0-15, flagged bit 16, overflow bit 17). */
#define PF_FLAGGED_BIT 0x10000u
#define PF_OVERFLOW_BIT 0x20000u
#define PF_REBUILT_BIT 0x40000u /* set by particle 0 on a step that rebuilt the lists */

/* Sums particle records [first, end) into one partial record at out. */
void pf_sum_records(__global const float4* S, uint first, uint end, uint n, __global float* out) {
  float ke = 0.0f, speed = 0.0f, disp = 0.0f;
  uint pairs = 0u, flagged = 0u, overflow = 0u, rebuilt = 0u;
  for (uint k = first; k < end; ++k) {
    const float4 r = S[k];
    const uint bits = as_uint(r.w);
    ke += r.x;
    speed = fmax(speed, r.y);
    disp = fmax(disp, r.z);
    pairs += bits & 0xFFFFu;
    flagged += (bits >> 16) & 1u;
    overflow += (bits >> 17) & 1u;
    rebuilt |= (bits >> 18) & 1u;
  }
  vstore4((float4)(ke, speed, disp, (float)rebuilt), 0, out);
  vstore4(as_float4((uint4)(pairs, flagged, overflow, n)), 1, out);
}

/* Sums `groups` partial records into one history record at out. */
void pf_sum_partials(__global const float* P, uint groups, __global float* out) {
  float4 f = (float4)(0.0f);
  uint4 u = (uint4)(0u);
  for (uint g = 0; g < groups; ++g) {
    const float4 pf = vload4(0, P + g * PF_RECORD);
    const uint4 pu = as_uint4(vload4(1, P + g * PF_RECORD));
    f = (float4)(f.x + pf.x, fmax(f.y, pf.y), fmax(f.z, pf.z), fmax(f.w, pf.w));
    u = (uint4)(u.x + pu.x, u.y + pu.y, u.z + pu.z, max(u.w, pu.w));
  }
  vstore4(f, 0, out);
  vstore4(as_float4(u), 1, out);
}

/* The reduction work that rides along a step: work-item k < chunk_groups
 * sums chunk k of the previous step's records; work-item 0 turns the
 * partials of the step before into its history record. */
void pf_reduce_in_flight(uint k, __global const float4* S_prev, uint n_prev, uint chunk, uint chunk_groups,
                         __global float* P_out, __global const float* P_prev, uint groups_prev2,
                         __global float* history, uint slot_prev2) {
  if (k < chunk_groups)
    pf_sum_records(S_prev, k * chunk, min(n_prev, (k + 1u) * chunk), n_prev, P_out + k * PF_RECORD);
  if (k == 0 && groups_prev2 > 0u) pf_sum_partials(P_prev, groups_prev2, history + slot_prev2 * PF_RECORD);
}

/* pf_lj_force_scale of physics.cl for 8 pairs at once, given 1/d^2 and
 * 1/d, with the prelude's constants (the same formula with the divisions
 * shared; the oracle tests tie the two). */
float8 pf_lj_force_scale8(float8 inv_d2, float8 inv_d) {
  const float8 x = PF_SIGMA2 * inv_d2;
#if PF_EXP_B_HALF > 0
  float8 sb = x;
  for (int k = 1; k < PF_EXP_B_HALF; ++k) sb *= x;
#else
  const float8 sb = pow(x, (float8)(0.5f * PF_EXP_B));
#endif
#if PF_EXP_B_HALF > 0 && PF_EXP_A_HALF == 2 * PF_EXP_B_HALF
  const float8 sa = sb * sb;
#elif PF_EXP_A_HALF > 0
  float8 sa = x;
  for (int k = 1; k < PF_EXP_A_HALF; ++k) sa *= x;
#else
  const float8 sa = pow(x, (float8)(0.5f * PF_EXP_A));
#endif
  const float8 k = 4.0f * PF_EPS * (PF_EXP_A * sa - PF_EXP_B * sb) * inv_d2;
  const float8 k_max = PF_FORCE_CAP * inv_d;
  return fmin(fmax(k, -k_max), k_max);
}

/* Lists every particle in the cells under `stamp`, on the steps whose
 * lists are rebuilt (force, or the last step raised request[request_read]);
 * otherwise returns at once. */
__kernel void insert_cells(__global const float4* X, __global uint* counts, __global float* slots, const uint stamp,
                           const float4 cell_origin, const float4 cell_inv, const int4 cell_dims, const uint n,
                           __global const uint* request, const uint request_read, const uint force) {
  const uint i = get_global_id(0);
  if (i >= n || !(force || request[request_read])) return;
  const float4 x = X[i];
  pf_cell_insert(counts, slots, pf_cell_index(pf_cell_of(x, cell_origin, cell_inv, cell_dims), cell_dims), stamp, i, x);
}

/* One birth: writes particle `index` (the next step rebuilds the lists). */
__kernel void birth_one(__global float4* X, __global float4* V, __global uint* flags, __global float* C,
                        const uint index, const float4 x, const float4 v) {
  if (get_global_id(0) != 0) return;
  X[index] = x;
  V[index] = v;
  flags[index] = 0u;
  C[index] = 0.0f;
}

/* One birth while the lists are valid (one launch over n + 1 items, n
 * the count before the birth): item i < n lists the newcomer b = n if its
 * reference position XREF[i] is within PF_RL of b, the rule the lists were
 * built by (b's reference is where it is born): a pair left out can only
 * come within reach after drifts from the references of more than the skin
 * in all, which the rebuild test (each drift at most half the skin) rules
 * out. It takes a slot in b's list (list_count[b] is 0 beforehand); item n
 * writes the newcomer. A full list raises the rebuild request the next step
 * reads. */
__kernel void birth_linked(__global float4* X, __global float4* V, __global uint* flags, __global float* C,
                           __global uint* list, __global uint* list_count, __global float4* XREF,
                           __global uint* request, const uint request_next, const uint n, const float4 x,
                           const float4 v) {
  const uint i = get_global_id(0);
  if (i == n) {
    X[n] = x;
    V[n] = v;
    flags[n] = 0u;
    C[n] = 0.0f;
    XREF[n] = x;
    return;
  }
  if (i > n) return;
  float4 d = XREF[i] - x;
  d.w = 0.0f;
  if (dot(d, d) >= PF_RL2) return;
  const uint mine = list_count[i];
  const uint slot = atomic_inc(&list_count[n]);
  if (mine < PF_LIST_CAP && slot < PF_LIST_CAP) {
    list[(size_t)i * PF_LIST_CAP + mine] = n;
    list_count[i] = mine + 1u;
    list[(size_t)n * PF_LIST_CAP + slot] = i;
  } else {
    atomic_or(&request[request_next], 1u);
  }
}

/* One removal while the lists are valid (one launch over n items, n the
 * count before it): particle `last` = n - 1 takes the place of `gone`. Item
 * `gone` copies the last particle's state and list (without `gone`); every
 * other item but `last` drops `gone` from its own list and renames `last`
 * to `gone`. The host then zeroes list_count[last]. */
__kernel void remove_linked(__global float4* X, __global float4* V, __global uint* flags, __global float* C,
                            __global uint* list, __global uint* list_count, __global float4* XREF, const uint n,
                            const uint gone) {
  const uint i = get_global_id(0);
  const uint last = n - 1u;
  if (i >= last) return;
  __global uint* row = list + (size_t)i * PF_LIST_CAP;
  if (i == gone) {
    X[i] = X[last];
    V[i] = V[last];
    flags[i] = flags[last];
    C[i] = C[last];
    XREF[i] = XREF[last];
    __global const uint* from = list + (size_t)last * PF_LIST_CAP;
    const uint count = min(list_count[last], PF_LIST_CAP);
    uint kept = 0u;
    for (uint k = 0; k < count; ++k)
      if (from[k] != gone) row[kept++] = from[k];
    list_count[i] = kept;
    return;
  }
  uint count = min(list_count[i], PF_LIST_CAP);
  for (uint k = 0; k < count;) {
    if (row[k] == gone) {
      row[k] = row[--count];
    } else {
      if (row[k] == last) row[k] = gone;
      ++k;
    }
  }
  list_count[i] = count;
}

/* One removal: particle `from` (the last) takes the place of `to`. */
__kernel void move_particle(__global float4* X, __global float4* V, __global uint* flags, __global float* C,
                            const uint from, const uint to) {
  if (get_global_id(0) != 0) return;
  X[to] = X[from];
  V[to] = V[from];
  flags[to] = flags[from];
  C[to] = C[from];
}

/* Finishes the steps in flight (one work-item): the record of the last
 * step (S_prev, if n_prev_valid) and the partials of the one before. */
__kernel void finalize_history(__global const float4* S_prev, const uint n_prev, const uint have_prev,
                               __global float* history, const uint slot_prev, __global const float* P_prev,
                               const uint groups_prev2, const uint slot_prev2) {
  if (get_global_id(0) != 0) return;
  if (groups_prev2 > 0u) pf_sum_partials(P_prev, groups_prev2, history + slot_prev2 * PF_RECORD);
  if (have_prev) pf_sum_records(S_prev, 0u, n_prev, n_prev, history + slot_prev * PF_RECORD);
}

/* For tests: the indices of each particle's neighbours (pairs the step
 * considers: d^2 < max(rc^2, (r_i + r_j)^2)), at most max_out each. */
__kernel void list_neighbours(__global const float4* X, __global const uint* counts, __global const float* slots,
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
          const uint j = as_uint(slots[cell * PF_BLOCK + PF_SLOT(k, 4u)]);
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

/* Sorts a list row (or a piece of one) by index (see pf_build_list). */
void pf_sort_row(__global uint* row, uint count) {
  for (uint k = 1; k < count; ++k) {
    const uint v = row[k];
    uint m = k;
    for (; m > 0 && row[m - 1] > v; --m) row[m] = row[m - 1];
    row[m] = v;
  }
}

/* One compare-exchange stage of a bitonic sorting network over 8 lanes:
 * each lane meets the lane `partner` (a swizzle of v) and keeps the smaller
 * value where take_lo is set, the larger elsewhere. */
#define PF_SORT_STAGE(v, partner, take_lo) \
  do { \
    const uint8 p_ = (partner); \
    v = select(max(v, p_), min(v, p_), (take_lo)); \
  } while (0)

/* The 8 lanes of v in ascending order (bitonic network, 6 stages). */
uint8 pf_sort8(uint8 v) {
  PF_SORT_STAGE(v, v.s10325476, (int8)(-1, 0, 0, -1, -1, 0, 0, -1));
  PF_SORT_STAGE(v, v.s23016745, (int8)(-1, -1, 0, 0, 0, 0, -1, -1));
  PF_SORT_STAGE(v, v.s10325476, (int8)(-1, 0, -1, 0, 0, -1, 0, -1));
  PF_SORT_STAGE(v, v.s45670123, (int8)(-1, -1, -1, -1, 0, 0, 0, 0));
  PF_SORT_STAGE(v, v.s23016745, (int8)(-1, -1, 0, 0, -1, -1, 0, 0));
  PF_SORT_STAGE(v, v.s10325476, (int8)(-1, 0, -1, 0, -1, 0, -1, 0));
  return v;
}

/* Rebuilds particle i's neighbour list from the cells: indices j != i
 * with |x_i - x_j|^2 < PF_RL2. Returns the count (capped at PF_LIST_CAP;
 * more set the overflow bit in *bits).
 *
 * Order: cell by cell in a fixed order, each cell's neighbours ascending by
 * index. The cells list particles in the order their atomic insertions
 * happened, which varies run to run on a multi-threaded device; this order
 * does not, so the forces sum in one order and the same input gives the
 * same particles. A chunk of 8 candidates is sorted in registers (the
 * lanes that are not neighbours become UINT_MAX and sort last) and stored
 * as one vector; a cell of more than 8 is sorted as a whole afterwards. */
uint pf_build_list(uint i, float4 xi, __global const uint* counts, __global const float* slots, uint stamp,
                   int4 c, int4 cell_dims, __global uint* row, uint* bits) {
  uint found = 0u;
  const int4 lo = max(c - (int4)(1), (int4)(0)), hi = min(c + (int4)(1), cell_dims - (int4)(1));
  for (int cz = lo.z; cz <= hi.z; ++cz)
    for (int cy = lo.y; cy <= hi.y; ++cy)
      for (int cx = lo.x; cx <= hi.x; ++cx) {
        const uint cell = (uint)(cx + cell_dims.x * (cy + cell_dims.y * cz));
        uint m = pf_cell_count(counts, cell, stamp);
        if (m > PF_CELL_CAP) {
          *bits |= PF_OVERFLOW_BIT;
          m = PF_CELL_CAP;
        }
        const uint cell_first = found;
        __global const float* block = slots + cell * PF_BLOCK;
        for (uint k = 0; k < m; k += 8u) {
          __global const float* chunk = block + 5u * k; /* k is a multiple of 8: chunk k / 8 */
          const float8 dx = xi.x - vload8(0, chunk), dy = xi.y - vload8(1, chunk), dz = xi.z - vload8(2, chunk);
          const uint8 jj = as_uint8(vload8(4, chunk));
          const int8 lane = (int8)(0, 1, 2, 3, 4, 5, 6, 7) + (int8)((int)k);
          const int8 near = (lane < (int8)((int)m)) & (jj != (uint8)(i)) & (dx * dx + dy * dy + dz * dz < PF_RL2);
          /* counted as floats: oclgrind (1.x) mis-sums lanes of integer masks */
          const float8 hit = select((float8)(0.0f), (float8)(1.0f), near);
          const uint hits = (uint)(hit.s0 + hit.s1 + hit.s2 + hit.s3 + hit.s4 + hit.s5 + hit.s6 + hit.s7);
          if (hits == 0u) continue;
          const uint8 sorted = pf_sort8(select((uint8)(UINT_MAX), jj, near));
          if (found + 8u <= PF_LIST_CAP) {
            vstore8(sorted, 0, row + found);
          } else {
            uint js[8];
            vstore8(sorted, 0, js);
            for (uint l = 0; l < hits && found + l < PF_LIST_CAP; ++l) row[found + l] = js[l];
          }
          found += hits;
        }
        if (m > 8u && found > cell_first) pf_sort_row(row + cell_first, min(found, PF_LIST_CAP) - min(cell_first, PF_LIST_CAP));
      }
  if (found > PF_LIST_CAP) {
    *bits |= PF_OVERFLOW_BIT;
    found = PF_LIST_CAP;
  }
  return found;
}

/* The wall's field: a global float buffer sampled by physics.cl
 * pf_sdf_sample (the default), or with PF_FIELD_IMAGE a CL_R / CL_FLOAT
 * image3d_t whose 8 corners are read with a NEAREST sampler at integer
 * coordinates and blended by the same trilinear formula in float, so the
 * value and the gradient are those of the buffer path (hardware LINEAR
 * filtering would round the weights to 8 bits on GPUs). */
#ifdef PF_FIELD_IMAGE
#define PF_FIELD_ARG __read_only image3d_t
#define PF_FIELD_SAMPLE pf_sdf_sample_image
__constant sampler_t pf_field_sampler = CLK_NORMALIZED_COORDS_FALSE | CLK_ADDRESS_CLAMP_TO_EDGE | CLK_FILTER_NEAREST;

float pf_field_at(__read_only image3d_t f, int i, int j, int k) {
  return read_imagef(f, pf_field_sampler, (int4)(i, j, k, 0)).x;
}

/* pf_sdf_sample (physics.cl) with the values read from the image. */
float pf_sdf_sample_image(__read_only image3d_t f, int nx, int ny, int nz, float ox, float oy, float oz,
                          float inv_spacing, float px, float py, float pz, float* g) {
  const float gx = fmin(fmax((px - ox) * inv_spacing, 0.0f), (float)(nx - 1));
  const float gy = fmin(fmax((py - oy) * inv_spacing, 0.0f), (float)(ny - 1));
  const float gz = fmin(fmax((pz - oz) * inv_spacing, 0.0f), (float)(nz - 1));
  const int i = min((int)floor(gx), nx - 2), j = min((int)floor(gy), ny - 2), k = min((int)floor(gz), nz - 2);
  const float tx = gx - (float)i, ty = gy - (float)j, tz = gz - (float)k;
  const float v000 = pf_field_at(f, i, j, k), v100 = pf_field_at(f, i + 1, j, k);
  const float v010 = pf_field_at(f, i, j + 1, k), v110 = pf_field_at(f, i + 1, j + 1, k);
  const float v001 = pf_field_at(f, i, j, k + 1), v101 = pf_field_at(f, i + 1, j, k + 1);
  const float v011 = pf_field_at(f, i, j + 1, k + 1), v111 = pf_field_at(f, i + 1, j + 1, k + 1);
  return pf_trilinear(v000, v100, v010, v110, v001, v101, v011, v111, tx, ty, tz, inv_spacing, g);
}
#else
#define PF_FIELD_ARG __global const float*
#define PF_FIELD_SAMPLE pf_sdf_sample
#endif

/* The whole update of one particle (see the top of the file), plus the
 * reduction work in flight. sdf_origin = (origin, 1/spacing), sdf_dims =
 * (nx, ny, nz, has_walls). Launched over max(n, chunk_groups, 1) items. */
__kernel void advance(__global const float4* X, __global const float4* V, __global float4* X_out,
                      __global float4* V_out, __global const uint* counts, __global const float* slots,
                      const uint stamp, const float4 cell_origin, const float4 cell_inv, const int4 cell_dims,
                      PF_FIELD_ARG sdf, const float4 sdf_origin, const int4 sdf_dims,
                      __global uint* flags, __global float* C, const uint n, __global float4* S_out,
                      __global const float4* S_prev, const uint n_prev, const uint chunk, const uint chunk_groups,
                      __global float* P_out, __global const float* P_prev, const uint groups_prev2,
                      __global float* history, const uint slot_prev2, __global uint* list, __global uint* list_count,
                      __global float4* XREF, __global uint* request, const uint request_read,
                      const uint request_raise, const uint request_clear, const uint force_rebuild,
                      const int4 sort_rows) {
  const uint i = get_global_id(0);
  pf_reduce_in_flight(i, S_prev, n_prev, chunk, chunk_groups, P_out, P_prev, groups_prev2, history, slot_prev2);
  if (i == 0) request[request_clear] = 0u;
  if (i >= n) return;
  const float4 xi = X[i];
  const float4 vi = V[i];
  const float ri = xi.w, inv_mi = vi.w;
  uint bits = 0u;
  __global uint* row = list + (size_t)i * PF_LIST_CAP;
  uint count;
  if (force_rebuild || request[request_read]) {
    count = pf_build_list(i, xi, counts, slots, stamp, pf_cell_of(xi, cell_origin, cell_inv, cell_dims), cell_dims,
                          row, &bits);
    list_count[i] = count;
    XREF[i] = xi;
    if (i == 0) bits |= PF_REBUILT_BIT;
  } else {
    count = min(list_count[i], PF_LIST_CAP);
    /* newcomers' lists were filled by atomics (birth_linked): sort them once */
    if (any((int4)((int)i) == sort_rows)) pf_sort_row(row, count);
  }
  float8 fx = (float8)(0.0f), fy = (float8)(0.0f), fz = (float8)(0.0f);
  int8 overlaps = (int8)(0); /* -1 per overlapping pair with j > i */
  for (uint k = 0; k < count; k += 8u) {
    const int8 lane = (int8)(0, 1, 2, 3, 4, 5, 6, 7) + (int8)((int)k);
    const int8 valid = lane < (int8)((int)count);
    const uint8 jj = select((uint8)(i), vload8(0, row + k), valid); /* past the count: i itself, masked below */
    const float4 p0 = X[jj.s0], p1 = X[jj.s1], p2 = X[jj.s2], p3 = X[jj.s3];
    const float4 p4 = X[jj.s4], p5 = X[jj.s5], p6 = X[jj.s6], p7 = X[jj.s7];
    float8 dx = xi.x - (float8)(p0.x, p1.x, p2.x, p3.x, p4.x, p5.x, p6.x, p7.x);
    float8 dy = xi.y - (float8)(p0.y, p1.y, p2.y, p3.y, p4.y, p5.y, p6.y, p7.y);
    float8 dz = xi.z - (float8)(p0.z, p1.z, p2.z, p3.z, p4.z, p5.z, p6.z, p7.z);
    const float8 rs = ri + (float8)(p0.w, p1.w, p2.w, p3.w, p4.w, p5.w, p6.w, p7.w);
    float8 d2 = dx * dx + dy * dy + dz * dz;
    const float8 touch2 = fmax(rs * rs, PF_CONTACT2);
    const int8 near = valid & (d2 < fmax(touch2, PF_RC2));
    if (!any(near)) continue;
    d2 = select((float8)(1.0f), d2, near); /* masked lanes stay finite */
    const int8 tiny = near & (d2 < PF_D_MIN * PF_D_MIN);
    if (any(tiny)) { /* on top of each other: a fixed, antisymmetric direction */
      dx = select(dx, select((float8)(PF_D_MIN), (float8)(-PF_D_MIN), jj > (uint8)(i)), tiny);
      dy = select(dy, (float8)(0.0f), tiny);
      dz = select(dz, (float8)(0.0f), tiny);
      d2 = select(d2, (float8)(PF_D_MIN * PF_D_MIN), tiny);
    }
    const float8 inv_d2 = 1.0f / d2, inv_d = sqrt(inv_d2);
    const float8 kf = select((float8)(0.0f), pf_lj_force_scale8(inv_d2, inv_d), near & (d2 < PF_RC2));
    fx += kf * dx;
    fy += kf * dy;
    fz += kf * dz;
    const int8 contact = near & (d2 < touch2);
    if (any(contact)) { /* dashpots (physics.cl pf_contact_damping, 8 lanes) */
      const float4 q0 = V[jj.s0], q1 = V[jj.s1], q2 = V[jj.s2], q3 = V[jj.s3];
      const float4 q4 = V[jj.s4], q5 = V[jj.s5], q6 = V[jj.s6], q7 = V[jj.s7];
      const float8 nx = dx * inv_d, ny = dy * inv_d, nz = dz * inv_d;
      const float8 un = (vi.x - (float8)(q0.x, q1.x, q2.x, q3.x, q4.x, q5.x, q6.x, q7.x)) * nx +
                        (vi.y - (float8)(q0.y, q1.y, q2.y, q3.y, q4.y, q5.y, q6.y, q7.y)) * ny +
                        (vi.z - (float8)(q0.z, q1.z, q2.z, q3.z, q4.z, q5.z, q6.z, q7.z)) * nz;
      const float8 imj = (float8)(q0.w, q1.w, q2.w, q3.w, q4.w, q5.w, q6.w, q7.w);
      const float8 cf = select((float8)(0.0f), -PF_DASHPOT * rsqrt(inv_mi + imj) * un, contact);
      fx += cf * nx;
      fy += cf * ny;
      fz += cf * nz;
      overlaps += contact & (d2 < rs * rs) & (jj > (uint8)(i));
    }
  }
  const uint pairs = (uint)(-(overlaps.s0 + overlaps.s1 + overlaps.s2 + overlaps.s3 + overlaps.s4 + overlaps.s5 +
                              overlaps.s6 + overlaps.s7));
  const float4 force = (float4)(fx.s0 + fx.s1 + fx.s2 + fx.s3 + fx.s4 + fx.s5 + fx.s6 + fx.s7,
                                fy.s0 + fy.s1 + fy.s2 + fy.s3 + fy.s4 + fy.s5 + fy.s6 + fy.s7,
                                fz.s0 + fz.s1 + fz.s2 + fz.s3 + fz.s4 + fz.s5 + fz.s6 + fz.s7, 0.0f);
  float4 u = vi;
  u.w = 0.0f;
  u = (u + (PF_DT * inv_mi) * force) * PF_DAMP;
  const float speed = length(u);
  if (speed > PF_VMAX) u *= PF_VMAX / speed; /* displacement cap: at most PF_VMAX dt a step */
  float4 xn = xi + PF_DT * u;
  xn.w = ri;
  if (sdf_dims.w != 0) {
    float clearance = C[i] - 2.0f * PF_DT * length(u);
    if (clearance <= 0.0f) {
      float g[3];
      float phi = PF_FIELD_SAMPLE(sdf, sdf_dims.x, sdf_dims.y, sdf_dims.z, sdf_origin.x, sdf_origin.y, sdf_origin.z,
                                sdf_origin.w, xn.x, xn.y, xn.z, g);
      const float4 grid_pos = (xn - sdf_origin) * sdf_origin.w;
      const int outside_box = grid_pos.x < 0.0f || grid_pos.y < 0.0f || grid_pos.z < 0.0f ||
                              grid_pos.x > (float)(sdf_dims.x - 1) || grid_pos.y > (float)(sdf_dims.y - 1) ||
                              grid_pos.z > (float)(sdf_dims.z - 1);
      if (phi > 0.0f || outside_box) {
        bits |= PF_FLAGGED_BIT;
        flags[i] = 1u;
      }
      if (phi > -ri) {
        for (int it = 0; it < PF_WALL_ITERATIONS && phi > -ri; ++it) {
          const float gl = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
          if (!(gl > 1e-20f)) break;
          const float push = (phi + ri) / gl;
          xn.x -= push * g[0];
          xn.y -= push * g[1];
          xn.z -= push * g[2];
          phi = PF_FIELD_SAMPLE(sdf, sdf_dims.x, sdf_dims.y, sdf_dims.z, sdf_origin.x, sdf_origin.y, sdf_origin.z,
                              sdf_origin.w, xn.x, xn.y, xn.z, g);
        }
        const float gl = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
        if (gl > 1e-20f) {
          const float4 nrm = (float4)(g[0], g[1], g[2], 0.0f) / gl;
          u += pf_wall_velocity_change(dot(u, nrm), PF_WALL_RESTITUTION) * nrm;
        }
      }
      clearance = outside_box ? 0.0f : fmax(-phi - ri, 0.0f);
    }
    C[i] = clearance;
  }
  X_out[i] = xn;
  V_out[i] = (float4)(u.x, u.y, u.z, inv_mi);
  float4 dxn = xn - xi;
  dxn.w = 0.0f;
  float4 drift = xn - XREF[i];
  drift.w = 0.0f;
  if (dot(drift, drift) > PF_HALF_SKIN2) atomic_or(&request[request_raise], 1u);
  S_out[i] = (float4)(0.5f * dot(u, u) / inv_mi, length(u), length(dxn), as_float(min(pairs, 0xFFFFu) | bits));
}
