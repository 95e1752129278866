/* gpu_step.cl: the GPU form's `advance` (after gpu_lists.cl and
 * field.cl): each work-item rebuilds its particle's list when due, sums
 * its pair forces in fixed point, integrates, meets the wall; the
 * per-step records are summed by work-groups in local memory. And
 * finalize_history. */

/* `advance` for particle i, from its state (xi, vi), the force on it and
 * its build bits: velocity Verlet with the displacement cap, the wall
 * (sampled only where the clearance bound runs out), the new state to
 * X_out and V_out, the list requests its drift raises. Returns its record.
 * The GPU form's; the CPU form's pf_advance8 does the same 8 at a time. */
/* physics.cl's wall push for one particle. */
#define PF_SAMPLE1(PX, PY, PZ, G, LANES)                                                                                 \
  PF_FIELD_SAMPLE(sdf, sdf_dims.x, sdf_dims.y, sdf_dims.z, sdf_origin.x, sdf_origin.y, sdf_origin.z, sdf_origin.w, PX, \
                  PY, PZ, G)
PF_DEFINE_WALL_PUSH(pf_wall_push, float, int, PF_ANY1, PF_SAMPLE1, pf_wall_velocity_change, PF_FIELD_ARG sdf,
                    float4 sdf_origin, int4 sdf_dims)

float8 pf_integrate(uint i, float4 xi, float4 vi, float4 force, uint bits, uint rebuilt, uint pairs,
                    __global float4* X_out, __global float4* V_out, PF_FIELD_ARG sdf, float4 sdf_origin, int4 sdf_dims,
                    __global uint* flags, __global float* C, __global const float4* XREF, __global uint* request,
                    uint request_raise, uint n, float8 fire_now, uint step_index) {
  const float ri = xi.w, inv_mi = vi.w;
  float ux = vi.x, uy = vi.y, uz = vi.z, px = xi.x, py = xi.y, pz = xi.z;
#if PF_FIRE
  /* the FIRE state's step, and the speed cap that keeps a step's move at PF_STEP_CAP */
  const float dt = fire_now.s0, vmax = PF_STEP_CAP / dt;
  const int restart = as_uint(fire_now.s5) == step_index;
  float fourth;
  const float speed = pf_fire_kick_drift(&ux, &uy, &uz, &px, &py, &pz, force.x, force.y, force.z, inv_mi, dt,
                                         fire_now.s1, restart, fire_now.s2, vmax, &fourth);
#else
  const float dt = PF_DT, vmax = PF_VMAX;
  const float fourth = (float)rebuilt;
  const float speed =
      pf_kick_drift(&ux, &uy, &uz, &px, &py, &pz, force.x, force.y, force.z, inv_mi, PF_DT, PF_DAMP, PF_VMAX);
#endif
  const float capped_speed = speed > vmax ? vmax : speed; /* |u| now */
  if (sdf_dims.w != 0) {
    float clearance = fma(-2.0f * dt, capped_speed, C[i]);
#if PF_FIRE
    /* a restart's back-up moved the centre outside the bound's count: the wall looks */
    const int wall_due = clearance <= 0.0f || restart;
#else
    const int wall_due = clearance <= 0.0f;
#endif
    if (wall_due) {
      float g[3];
      float phi = PF_FIELD_SAMPLE(sdf, sdf_dims.x, sdf_dims.y, sdf_dims.z, sdf_origin.x, sdf_origin.y, sdf_origin.z,
                                sdf_origin.w, px, py, pz, g);
      const float4 grid_pos = ((float4)(px, py, pz, 0.0f) - sdf_origin) * sdf_origin.w;
      const int outside_box = grid_pos.x < 0.0f || grid_pos.y < 0.0f || grid_pos.z < 0.0f ||
                              grid_pos.x > (float)(sdf_dims.x - 1) || grid_pos.y > (float)(sdf_dims.y - 1) ||
                              grid_pos.z > (float)(sdf_dims.z - 1);
      if (phi > 0.0f || outside_box) {
        bits |= PF_FLAGGED_BIT;
        flags[i] = 1u;
      }
      phi = pf_wall_push(&px, &py, &pz, &ux, &uy, &uz, phi, g, phi > -ri, ri, PF_WALL_RESTITUTION, sdf, sdf_origin,
                         sdf_dims);
      clearance = outside_box ? 0.0f : fmax(-phi - ri, 0.0f);
    }
    C[i] = clearance;
  }
  const float4 u = (float4)(ux, uy, uz, 0.0f);
  const float4 xn = (float4)(px, py, pz, ri);
  X_out[i] = xn;
  V_out[i] = (float4)(u.x, u.y, u.z, inv_mi);
  if (pf_norm2(xn - XREF[i]) > PF_HALF_SKIN2) atomic_or(&request[request_raise], PF_REQUEST_REBUILD);
  const float u2 = pf_norm2(u);
  return pf_record(0.5f * u2 / inv_mi, u2, pf_norm2(xn - xi), fourth, pairs, (bits & PF_FLAGGED_BIT) ? 1u : 0u,
                   (bits & PF_OVERFLOW_BIT) ? 1u : 0u, n);
}

/* The whole update of one particle a work-item (ping-pong: reads X and
 * V, writes X_out and V_out), plus the reductions in flight: the list
 * rebuild when due (from the cells, count words from cell_base on), the
 * pair forces over the particle's full list one pair at a time, then
 * pf_integrate. sdf_origin = (origin, 1/spacing), sdf_dims = (nx, ny, nz,
 * has_walls). Work-items: at least one a particle, and a group for each
 * level-2 partial of the last step. L1_out / L2_out: this step's level-1
 * partials and the last step's level-2 ones; L1_prev: the last step's
 * level-1 partials (g1_prev; 0: none); L2_prev: the level-2 partials of
 * the step before (g2_prev2; 0: none), whose record goes to
 * history[slot_prev2]. Request words (cells.cl): read request_read, raise
 * request_raise, clear request_clear. */
__kernel __attribute__((reqd_work_group_size(PF_WG, 1, 1))) void advance(
    __global const float4* X, __global const float4* V, __global float4* X_out, __global float4* V_out,
    __global const uint* counts, __global const float* slots, const uint cell_base, const float4 cell_origin,
    const float4 cell_inv, const int4 cell_dims, PF_FIELD_ARG sdf, const float4 sdf_origin, const int4 sdf_dims,
    __global uint* flags, __global float* C, const uint n, __global float8* L1_out, __global const float8* L1_prev,
    const uint g1_prev, __global float8* L2_out, __global const float8* L2_prev, const uint g2_prev2,
    __global float8* history, const uint slot_prev2, __global uint* list, __global uint* list_count,
    __global float4* XREF, __global uint* request, const uint request_read, const uint request_raise,
    const uint request_clear, const uint force_rebuild, __global float8* fire, const uint fire_read,
    const uint fire_write, const uint step_index) {
  __local float8 part[3u * PF_WG];
  __local float8 mid[3u * PF_WG_ROOT];
  const uint i = get_global_id(0), lid = get_local_id(0), group = get_group_id(0);
  if (i == 0) request[request_clear] = 0u;
  const float8 fire_now = PF_FIRE ? fire[fire_read] : (float8)(0.0f);
  float8 record = (float8)(0.0f);
  if (i < n) {
    const float4 xi = X[i];
    const float4 vi = V[i];
    const float ri = xi.w, inv_mi = vi.w;
    uint bits = 0u, rebuilt = 0u;
    __global uint* row = PF_ROW(list, i);
    uint count;
    if (force_rebuild || (request[request_read] & PF_REQUEST_REBUILD)) {
      const int4 c = pf_cell_of(xi, cell_origin, cell_inv, cell_dims);
      const float4 frac = (xi - cell_origin) * cell_inv - convert_float4(c);
      count = pf_build_list(i, xi, counts + cell_base, slots, c, frac, cell_inv.x, cell_dims, row, &bits);
      list_count[i] = count;
      XREF[i] = xi;
      rebuilt = i == 0u;
    } else {
      count = min(list_count[i], PF_LIST_CAP);
    }
    /* one pair at a time (GPUs: few registers, many warps in flight),
     * physics.cl's scalar formulas; the forces sum in 64-bit fixed point
     * (PF_FIX_SCALE units), exact and so the same in any list order. A
     * pair's force is at most PF_FIX_MAX = 2^14 force caps (the cap bounds
     * the potential's part; this only bounds the dashpot's), and
     * PF_FIX_SCALE = 2^47 / (force cap x list capacity), so sums stay
     * below 2^61 and resolve 2^-40 of the cap for a list of 128. */
    long fx = 0, fy = 0, fz = 0;
    uint pairs = 0u;
    for (uint k = 0; k < count; k += 4u) {
      /* four entries' loads issued together (latency overlaps when few warps run) */
      uint js[4];
      float4 xs[4];
#pragma unroll
      for (uint q = 0; q < 4u; ++q) js[q] = i; /* past the count: i, skipped */
      const uint4 group = vload4(0, &PF_AT(row, k)); /* k is a multiple of 4: one 16-byte load */
      js[0] = group.x; /* entry k < count */
      if (k + 1u < count) js[1] = group.y;
      if (k + 2u < count) js[2] = group.z;
      if (k + 3u < count) js[3] = group.w;
#pragma unroll
      for (uint q = 0; q < 4u; ++q) xs[q] = X[js[q]];
#pragma unroll
      for (uint q = 0; q < 4u; ++q) {
        const uint j = js[q];
        const float4 xj = xs[q];
        float4 d = xi - xj;
        d.w = 0.0f;
        const float rs = ri + xj.w;
        const float q2 = PF_PAIR_Q2(rs); /* the pair's scale squared (1 for equal spheres) */
        const float q = PF_PAIR_Q(rs);   /* and the scale: energy q^3, dashpot */
        const float rc2 = PF_RC2 * q2;
        float d2 = dot(d, d);
        const float touch2 = fmax(rs * rs, PF_CONTACT2 * q2);
        if (j == i || !(d2 < fmax(touch2, rc2))) continue;
        if (d2 < PF_D_MIN * PF_D_MIN) { /* on top of each other (physics.cl pf_apart) */
          float dx = d.x, dy = d.y, dz = d.z;
          pf_apart(&dx, &dy, &dz, &d2, 1, j > i, PF_D_MIN);
          d = (float4)(dx, dy, dz, 0.0f);
        }
        float4 f = pf_lj_force_scale(d2, PF_SIGMA2 * q2, PF_EPS, PF_EXP_A, PF_EXP_B, PF_EXP_A_HALF, PF_EXP_B_HALF, rc2,
                                     PF_FORCE_CAP, q2 * q) * d;
        if (d2 < touch2) {
          const float4 vj = V[j];
          const float4 nrm = d * rsqrt(d2);
          float4 du = vi - vj;
          du.w = 0.0f;
          f += pf_contact_damping(dot(du, nrm), inv_mi, vj.w, PF_DASHPOT, q) * nrm;
          if (d2 < rs * rs && j > i) ++pairs;
        }
        f = fmin(fmax(f, (float4)(-PF_FIX_MAX)), (float4)(PF_FIX_MAX)); /* so that no sum leaves 63 bits */
        fx += (long)(f.x * PF_FIX_SCALE);
        fy += (long)(f.y * PF_FIX_SCALE);
        fz += (long)(f.z * PF_FIX_SCALE);
      }
    }
    const float4 force = (float4)((float)fx, (float)fy, (float)fz, 0.0f) * (1.0f / PF_FIX_SCALE);
    record = pf_integrate(i, xi, vi, force, bits, rebuilt, pairs, X_out, V_out, sdf, sdf_origin, sdf_dims, flags, C,
                          XREF, request, request_raise, n, fire_now, step_index);
  }
  /* the reductions: this step's level 1, the last step's level 2, the step before's record */
  const uint g2_prev = (g1_prev + PF_WG - 1u) / PF_WG;
  part[lid] = record;
  if (group < g2_prev) part[PF_WG + lid] = pf_partial_at(L1_prev, g1_prev, group * PF_WG, lid);
  if (group == 0u && g2_prev2 > 0u) part[2u * PF_WG + lid] = pf_partials_strided(L2_prev, g2_prev2, lid);
  barrier(CLK_LOCAL_MEM_FENCE);
  const uint need = 1u | (group < g2_prev ? 2u : 0u) | (group == 0u && g2_prev2 > 0u ? 4u : 0u);
  const float8 s = pf_group_sums(part, mid, lid, need);
  if (lid == 0u && group < max((n + PF_WG - 1u) / PF_WG, 1u)) L1_out[group] = s;
  if (lid == 1u && group < g2_prev) L2_out[group] = s;
  if (lid == 2u && group == 0u && g2_prev2 > 0u) history[slot_prev2] = s;
#if PF_FIRE
  if (lid == 2u && group == 0u) fire[fire_write] = pf_fire_after(fire_now, s, g2_prev2 > 0u, step_index);
#endif
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
  __local float8 part[3u * PF_WG];
  __local float8 mid[3u * PF_WG_ROOT];
  for (uint c = 0; c < g2; ++c) {
    part[PF_WG + lid] = pf_partial_at(L1_last, g1, c * PF_WG, lid);
    barrier(CLK_LOCAL_MEM_FENCE);
    const float8 s = pf_group_sums(part, mid, lid, 2u);
    if (lid == 1u) L2_scratch[c] = s;
    barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
  }
  part[PF_WG + lid] = g2 > 0u ? pf_partials_strided(L2_scratch, g2, lid) : (float8)(0.0f);
  part[2u * PF_WG + lid] = g2_prev > 0u ? pf_partials_strided(L2_prev, g2_prev, lid) : (float8)(0.0f);
  barrier(CLK_LOCAL_MEM_FENCE);
  const float8 s = pf_group_sums(part, mid, lid, 6u);
  if (lid == 1u && g2 > 0u) history[slot_last] = s;
  if (lid == 2u && g2_prev > 0u) history[slot_prev] = s;
#if PF_FIRE
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lid == 1u || lid == 2u) part[lid] = s; /* the two records, for item 0 */
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lid == 0u) pf_fire_finish(fire, fire_slot, step_last, part[2], g2_prev > 0u, part[1], g2 > 0u);
#endif
}

