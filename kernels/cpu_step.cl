/* cpu_step.cl: the CPU form's `advance` (after cpu_pairs.cl, whose
 * pair_forces runs before it): the force buffers' sums, the integration,
 * the wall (with each particle's kept cell of the field), the list
 * requests, and the per-step records, an octet of particles at a time as
 * float8 lanes; and finalize_history. */

/* The lanes whose new position (x, y, z) lies more than sqrt(limit2)
 * from ref[0..7] (where the lists were built or pruned). */
int8 pf_drifted8(__global const float4* ref, float8 x, float8 y, float8 z, float limit2) {
  float4 t[8];
#pragma unroll
  for (uint l = 0; l < 8u; ++l) t[l] = ref[l];
  float8 a, b, c, d;
  pf_transpose8(t, &a, &b, &c, &d);
  return pf_norm2_8(x - a, y - b, z - c) > limit2;
}

/* The wall's kept cells: particle i keeps the cell it last sampled the
 * field in (kept_cell[i], its first sample's index; PF_NO_CELL: none) and
 * that cell's 8 corner values (kept_corners: per octet of particles, 8
 * float8s, corner c of the octet's lanes in the octet's c-th, corners in
 * pf_trilinear's order). A sphere against the wall samples the field every
 * step but stays in one cell for many, and its 8 corners, gathered from 4
 * cache lines far apart in a field of up to 256 MiB, were most of
 * pf_field_sample8's time (the stall at the first gather); kept, they are
 * 8 reads of 32 bytes in particle order. An entry is the corners of its
 * cell whichever particle wrote it, so births, removals and sorts leave
 * the entries true; only a new field or new memory must reset them to
 * PF_NO_CELL (ParticleArrays). */
#define PF_NO_CELL 0xffffffffu
#ifndef PF_FIELD_IMAGE
/* pf_field_sample8 at the lanes of octet i0, their kept corners read
 * where their cell is still the kept one, the field's corners gathered
 * (and kept) where not: the same corner values, so the same result to the
 * bit. */
float8 pf_field_sample8_kept(__global const float* f, int4 dims, float4 origin, float8 px, float8 py, float8 pz,
                             float8* g, int8 lanes, __global uint* kept_cell, __global float8* kept_corners, uint i0) {
  float8 t[3], v[8];
  const int8 base = pf_field_cell8(dims, origin, px, py, pz, t);
  const int8 cells = as_int8(vload8(0, kept_cell + i0)), miss = lanes & (cells != base);
  __global float8* c = kept_corners + i0; /* the octet's 8 float8s (i0 is a multiple of 8) */
#pragma unroll
  for (uint q = 0; q < 8u; ++q) v[q] = select(c[q], 0.0f, ~lanes); /* lanes not asked for read 0, as gathers give */
  if (pf_any8(miss)) {
    float8 fresh[8];
    pf_field_corners8(f, dims, base, miss, fresh);
#pragma unroll
    for (uint q = 0; q < 8u; ++q) {
      v[q] = select(v[q], fresh[q], miss);
      c[q] = select(c[q], fresh[q], miss); /* kept: the octet's other lanes keep theirs */
    }
    vstore8(as_uint8(select(cells, base, miss)), 0, kept_cell + i0);
  }
  return pf_trilinear8(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], t[0], t[1], t[2], (float8)(origin.w), g);
}
#else
#define pf_field_sample8_kept(f, dims, origin, px, py, pz, g, lanes, kept_cell, kept_corners, i0) \
  pf_field_sample8(f, dims, origin, px, py, pz, g, lanes)
#endif

/* physics.cl's rules at 8 lanes. */
PF_DEFINE_KICK_DRIFT(pf_kick_drift8, float8)
PF_DEFINE_FIRE_KICK_DRIFT(pf_fire_kick_drift8, float8, int8)
PF_DEFINE_WALL_VELOCITY_CHANGE(pf_wall_velocity_change8, float8)
#ifndef PF_KEPT_CELLS
#define PF_KEPT_CELLS 1 /* the wall's kept cells (above); 0: every sample gathers (tests, benchmarks) */
#endif
#if PF_KEPT_CELLS
#define PF_SAMPLE8(PX, PY, PZ, G, LANES) \
  pf_field_sample8_kept(sdf, sdf_dims, sdf_origin, PX, PY, PZ, G, LANES, kept_cell, kept_corners, i0)
#else
#define PF_SAMPLE8(PX, PY, PZ, G, LANES) pf_field_sample8(sdf, sdf_dims, sdf_origin, PX, PY, PZ, G, LANES)
#endif
PF_DEFINE_WALL_PUSH(pf_wall_push8, float8, int8, pf_any8, PF_SAMPLE8, pf_wall_velocity_change8, PF_FIELD_ARG sdf,
                    float4 sdf_origin, int4 sdf_dims, __global uint* kept_cell, __global float8* kept_corners, uint i0)

/* Eight lanes' new state: position p, velocity u, wall clearance, and
 * which lanes the wall found outside. */
typedef struct {
  float8 px, py, pz, ux, uy, uz, clearance;
  int8 flagged;
} pf_lanes8;

/* pf_integrate's wall for the `near` lanes of s (their clearance bound ran
 * out), 8 at a time: the field sampled at the new positions, the lanes
 * found outside flagged, a sphere closer to the surface than its radius r
 * pushed back along the gradient and its outward normal velocity
 * reflected; the near lanes' new clearance. (State by value: pointers
 * into the caller's vectors would keep them in memory.) */
pf_lanes8 pf_wall8(pf_lanes8 s, int8 near, float8 r, PF_FIELD_ARG sdf, float4 sdf_origin, int4 sdf_dims,
                   __global uint* kept_cell, __global float8* kept_corners, uint i0) {
  float8 g[3];
  float8 phi = PF_SAMPLE8(s.px, s.py, s.pz, g, near);
  const float8 grid_x = (s.px - sdf_origin.x) * sdf_origin.w, grid_y = (s.py - sdf_origin.y) * sdf_origin.w,
               grid_z = (s.pz - sdf_origin.z) * sdf_origin.w;
  const int8 outside_box = grid_x < 0.0f | grid_y < 0.0f | grid_z < 0.0f | grid_x > (float)(sdf_dims.x - 1) |
                           grid_y > (float)(sdf_dims.y - 1) | grid_z > (float)(sdf_dims.z - 1);
  s.flagged = near & ((phi > 0.0f) | outside_box);
  phi = pf_wall_push8(&s.px, &s.py, &s.pz, &s.ux, &s.uy, &s.uz, phi, g, near & (phi > -r), r,
                      (float8)(PF_WALL_RESTITUTION), sdf, sdf_origin, sdf_dims, kept_cell, kept_corners, i0);
  s.clearance = select(s.clearance, select(fmax(-phi - r, 0.0f), (float8)(0.0f), outside_box), near);
  return s;
}

/* `advance` for the particles i0..i0+7 below n as float8 lanes (the CPU
 * form's octets; the last may be partial: its lanes past n compute on
 * whatever lies there, within the buffers' capacity, a multiple of 8, and
 * are neither stored nor counted): the force buffers' sums
 * (w: overlapping pairs; zeroed for the next step), then pf_integrate's
 * physics on all lanes at once, the wall (pf_wall8) only where a lane's
 * clearance bound ran out. Every lane does the same operations whatever
 * its neighbours, so which particles share an octet changes no result.
 * Returns the octet's record, by vector sums and maxima (a loop over the
 * lanes cost far more). PoCL runs `advance`'s work-items one
 * after the other, scalar, so octets give it SIMD. */
float8 pf_advance8(uint i0, __global float4* X, __global float4* V, PF_FIELD_ARG sdf, float4 sdf_origin,
                   int4 sdf_dims, __global uint* kept_cell, __global float8* kept_corners, __global uint* flags,
                   __global float* C, __global const float4* XREF, __global const float4* XPRUNE,
                   __global uint* request, uint request_raise, uint rebuild, __global float4* F, uint force_groups,
                   uint force_stride, __global const uint2* force_spans, __global const uint* build_bits, uint n,
                   float8 fire_now, uint step_index) {
  const uint live_count = min(8u, n - i0);
  const int8 live = (int8)(0, 1, 2, 3, 4, 5, 6, 7) < (int8)((int)live_count);
  float4 xs[8], vs[8], t[8];
#pragma unroll
  for (uint l = 0; l < 8u; ++l) {
    xs[l] = X[i0 + l];
    vs[l] = V[i0 + l];
  }
  float8 x, y, z, r, vx, vy, vz, im;
  pf_transpose8(xs, &x, &y, &z, &r);
  pf_transpose8(vs, &vx, &vy, &vz, &im);
  /* the force buffers' sums (w: overlapping pairs), zeroed for the next
   * step (past n: zero, and cleared again; capacities are multiples of 8) */
  float8 fx = (float8)(0.0f), fy = fx, fz = fx, fw = fx;
  for (uint g = 0; g < force_groups; ++g) {
#if PF_NEWTON
    const uint2 span = force_spans[g];
    if (i0 + 8u <= span.x || i0 >= span.y) continue; /* zero there: pair_forces wrote elsewhere */
#endif
    __global float4* Fg = F + (size_t)g * force_stride + i0;
#pragma unroll
    for (uint l = 0; l < 8u; ++l) t[l] = Fg[l];
    float8 a, b, c, d;
    pf_transpose8(t, &a, &b, &c, &d);
    fx += a;
    fy += b;
    fz += c;
    fw += d;
#pragma unroll
    for (uint l = 0; l < 8u; ++l) Fg[l] = (float4)(0.0f);
  }
  uint8 bits = rebuild ? vload8(0, build_bits + i0) : (uint8)(0u);
  float8 ux = vx, uy = vy, uz = vz, px = x, py = y, pz = z;
#if PF_FIRE
  /* the FIRE state's step, and the speed cap that keeps a step's move at PF_STEP_CAP */
  const float dt = fire_now.s0, vmax = PF_STEP_CAP / dt;
  const int8 restart = (int8)(as_uint(fire_now.s5) == step_index ? -1 : 0);
  float8 power;
  const float8 speed = pf_fire_kick_drift8(&ux, &uy, &uz, &px, &py, &pz, fx, fy, fz, im, (float8)(dt),
                                           (float8)(fire_now.s1), restart, (float8)(fire_now.s2), (float8)(vmax),
                                           &power);
  const float fourth = pf_hsum8(select((float8)(0.0f), power, live));
#else
  const float dt = PF_DT, vmax = PF_VMAX;
  const float8 speed =
      pf_kick_drift8(&ux, &uy, &uz, &px, &py, &pz, fx, fy, fz, im, (float8)(PF_DT), (float8)(PF_DAMP), (float8)(PF_VMAX));
  const float fourth = rebuild && i0 == 0u ? 1.0f : 0.0f;
#endif
  pf_lanes8 s;
  s.ux = ux;
  s.uy = uy;
  s.uz = uz;
  s.px = px;
  s.py = py;
  s.pz = pz;
  const int8 fast = speed > vmax; /* capped: at most vmax dt a step */
  if (sdf_dims.w != 0) {
    const float8 old_clearance = vload8(0, C + i0);
    s.clearance = fma(-2.0f * dt, select(speed, (float8)(vmax), fast), old_clearance);
#if PF_FIRE
    /* a restart's back-up moved the centres outside the bound's count: the wall looks at them all */
    const int8 near = live & ((s.clearance <= 0.0f) | restart);
#else
    const int8 near = live & (s.clearance <= 0.0f);
#endif
    if (pf_any8(near)) {
      s = pf_wall8(s, near, r, sdf, sdf_origin, sdf_dims, kept_cell, kept_corners, i0);
      if (pf_any8(s.flagged)) {
        bits |= select((uint8)(0u), (uint8)(PF_FLAGGED_BIT), s.flagged);
        int fl[8];
        vstore8(s.flagged, 0, fl);
        for (uint l = 0; l < 8u; ++l)
          if (fl[l] != 0) flags[i0 + l] = 1u;
      }
    }
    vstore8(select(old_clearance, s.clearance, live), 0, C + i0);
  }
  float4 xo[8], vo[8];
  pf_untranspose8(s.px, s.py, s.pz, r, xo);
  pf_untranspose8(s.ux, s.uy, s.uz, im, vo);
  /* (unrolled with constant lanes: a loop to live_count would keep xo and vo in memory) */
#pragma unroll
  for (uint l = 0; l < 8u; ++l) {
    if (l < live_count) {
      X[i0 + l] = xo[l];
      V[i0 + l] = vo[l];
    }
  }
  /* the list requests the lanes' drift raises */
  if (pf_any8(live & pf_drifted8(XREF + i0, s.px, s.py, s.pz, PF_HALF_SKIN2)))
    atomic_or(&request[request_raise], PF_REQUEST_REBUILD);
#if PF_INNER
  if (pf_any8(live & pf_drifted8(XPRUNE + i0, s.px, s.py, s.pz, PF_HALF_INNER2)))
    atomic_or(&request[request_raise], PF_REQUEST_PRUNE);
#endif
  /* the record: sums and maxima over the live lanes */
  const float8 u2 = pf_norm2_8(s.ux, s.uy, s.uz);
  const float8 ke = 0.5f * u2 / im, disp2 = pf_norm2_8(s.px - x, s.py - y, s.pz - z);
  const uint8 one = (uint8)(1u), none = (uint8)(0u);
  return pf_record(pf_hsum8(select((float8)(0.0f), ke, live)), pf_hmax8(select((float8)(0.0f), u2, live)),
                   pf_hmax8(select((float8)(0.0f), disp2, live)), fourth,
                   pf_hsum8u(select(none, convert_uint8(fw), live)),
                   pf_hsum8u(select(none, one, live & ((bits & PF_FLAGGED_BIT) != 0u))),
                   pf_hsum8u(select(none, one, live & ((bits & PF_OVERFLOW_BIT) != 0u))), n);
}

/* The update of the particles (pf_advance8, an octet a work-item, the
 * last octet maybe partial), in place, plus the reductions in flight.
 * pair_forces (cpu_pairs.cl) left the forces in F (force_groups buffers,
 * force_stride apart; with PF_NEWTON buffer g is nonzero only for the
 * particles in force_spans[g]) and the list build's overflow bits in
 * build_bits. sdf_origin = (origin, 1/spacing), sdf_dims = (nx, ny, nz,
 * has_walls); kept_cell / kept_corners: the particles' kept cells of the
 * field (pf_field_sample8_kept). Work-items: one an octet, and a group for each level-2
 * partial of the last step. L1_out / L2_out: this step's level-1 partials
 * and the last step's level-2 ones; L1_prev: the last step's level-1
 * partials (g1_prev; 0: none); L2_prev: the level-2 partials of the step
 * before (g2_prev2; 0: none), whose record goes to history[slot_prev2].
 * Request words (cells.cl): read request_read, raise request_raise, clear
 * request_clear. */
__kernel __attribute__((reqd_work_group_size(PF_WG, 1, 1))) void advance(
    __global float4* X, __global float4* V, PF_FIELD_ARG sdf, const float4 sdf_origin, const int4 sdf_dims,
    __global uint* kept_cell, __global float8* kept_corners, __global uint* flags, __global float* C, const uint n,
    __global float8* L1_out, __global const float8* L1_prev, const uint g1_prev, __global float8* L2_out,
    __global const float8* L2_prev, const uint g2_prev2,
    __global float8* history, const uint slot_prev2, __global const float4* XREF, __global const float4* XPRUNE,
    __global uint* request, const uint request_read, const uint request_raise, const uint request_clear,
    const uint force_rebuild, __global float4* F, const uint force_groups, const uint force_stride,
    __global const uint2* force_spans, __global const uint* build_bits, __global float8* fire, const uint fire_read,
    const uint fire_write, const uint step_index) {
  const uint i = get_global_id(0), lid = get_local_id(0), group = get_group_id(0);
  if (i == 0) request[request_clear] = 0u;
  float8 record = (float8)(0.0f);
  /* Work-item t takes the octet 8t..8t+7 (the last may be partial) and
   * writes level-1 record t. One item an octet: PoCL runs a group's items
   * one after the other, and idle ones cost time too. */
  const uint rebuild = force_rebuild || (request[request_read] & PF_REQUEST_REBUILD);
  if (i < (n + 7u) / 8u) {
    L1_out[i] = pf_advance8(8u * i, X, V, sdf, sdf_origin, sdf_dims, kept_cell, kept_corners, flags, C, XREF, XPRUNE,
                            request, request_raise, rebuild, F, force_groups, force_stride, force_spans, build_bits,
                            n, PF_FIRE ? fire[fire_read] : (float8)(0.0f), step_index);
  } else if (i == 0u) {
    L1_out[0] = record; /* no particles: one empty record */
  }
  /* the reductions: this step's level 1, the last step's level 2, the step before's record */
  const uint g2_prev = (g1_prev + PF_WG - 1u) / PF_WG;
  /* chunk `group` by the group's first item, so that the chunks spread over the cores */
  if (lid == 0u && group < g2_prev)
    L2_out[group] = pf_partials_serial(L1_prev, group * PF_WG, min(g1_prev, (group + 1u) * PF_WG));
  if (i == 0u) {
    const float8 h = g2_prev2 > 0u ? pf_partials_serial(L2_prev, 0u, g2_prev2) : (float8)(0.0f);
    if (g2_prev2 > 0u) history[slot_prev2] = h;
#if PF_FIRE
    fire[fire_write] = pf_fire_after(fire[fire_read], h, g2_prev2 > 0u, step_index);
#endif
  }
}

/* Finishes the steps in flight (one work-group), by the same sums the
 * steps would have done: the last step's level-1 partials (L1_last, g1 of
 * them; 0: none) into level 2 (L2_scratch), then into its history record;
 * and the step before's level-2 partials (L2_prev, g2_prev; 0: none) into
 * its record. */
__kernel __attribute__((reqd_work_group_size(PF_WG, 1, 1))) void finalize_history(
    __global const float8* L1_last, const uint g1, __global float8* L2_scratch, __global const float8* L2_prev,
    const uint g2_prev, __global float8* history, const uint slot_last, const uint slot_prev, __global float8* fire,
    const uint fire_slot, const uint step_last) {
  const uint lid = get_local_id(0);
  const uint g2 = (g1 + PF_WG - 1u) / PF_WG;
  if (lid != 0u) return;
  for (uint c = 0; c < g2; ++c) L2_scratch[c] = pf_partials_serial(L1_last, c * PF_WG, min(g1, (c + 1u) * PF_WG));
  const float8 last = g2 > 0u ? pf_partials_serial(L2_scratch, 0u, g2) : (float8)(0.0f);
  const float8 prev = g2_prev > 0u ? pf_partials_serial(L2_prev, 0u, g2_prev) : (float8)(0.0f);
  if (g2 > 0u) history[slot_last] = last;
  if (g2_prev > 0u) history[slot_prev] = prev;
#if PF_FIRE
  pf_fire_finish(fire, fire_slot, step_last, prev, g2_prev > 0u, last, g2 > 0u);
#endif
}

