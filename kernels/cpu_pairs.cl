/* cpu_pairs.cl: the CPU form's pair forces (after cpu_lists.cl and
 * field.cl), launched before `advance` (cpu_step.cl).
 *
 * `pair_forces` takes 8 list entries at a time as float8 vectors (PoCL
 * turns them into SIMD). With PF_NEWTON it computes each listed pair once
 * and adds its force to both particles (Newton's third law: half the pair
 * work of listing pairs twice): a few work-items (one per core) each take
 * a block of particles and sum into a force buffer of their own, so
 * nothing is written by two at once; `advance` adds the buffers up and
 * zeroes them. That costs `advance` a read of every buffer for every
 * particle, so on many cores (EngineParams::newton) each pair is listed
 * twice instead and pair_forces writes each particle's force once. With
 * PF_PAIR_QUEUE (purely repulsive potentials: short rows, few entries in
 * reach) the rows are only tested and the entries in reach queued, then
 * computed 8 pairs at a time across rows (pf_queue_push). */

/* physics.cl's rules at 8 lanes. */
PF_DEFINE_POW_HALF(pf_pow_half8, float8)
PF_DEFINE_APART(pf_apart8, float8, int8)
PF_DEFINE_CONTACT_DAMPING(pf_contact_damping8, float8, pf_rsqrt8)

/* physics.cl's Lennard-Jones force scale for 8 pairs, given 1/d^2 and 1/d,
 * with the prelude's constants, sigma^2 scaled by the pairs' q2 (PF_PAIR_Q2_8),
 * the energy by q2 q (q: PF_PAIR_Q_8). */
PF_DEFINE_LJ_FORCE_SCALE(pf_lj_force_scale_inv8, float8, pf_pow_half8)
float8 pf_lj_force_scale8(float8 inv_d2, float8 inv_d, float8 q2, float8 q) {
  return pf_lj_force_scale_inv8(inv_d2, inv_d, PF_SIGMA2 * q2, PF_EPS, PF_EXP_A, PF_EXP_B, PF_EXP_A_HALF, PF_EXP_B_HALF,
                                PF_FORCE_CAP, q2 * q);
}

/* The `valid` lanes' entries jj into the running lowest and highest. */
void pf_span_add8(uint8* jlo, uint8* jhi, uint8 jj, int8 valid) {
  *jlo = min(*jlo, select((uint8)(UINT_MAX), jj, valid));
  *jhi = max(*jhi, select((uint8)(0u), jj, valid));
}

/* F at entry jj[l] (PF_ENTRY) -= (gx, gy, gz, 0).sl for the 8 lanes, one
 * read-modify-write a lane (the lanes' entries differ, except lanes past a
 * row's end, which hold stale entries and a zero force). */
void pf_scatter_sub8(__global float4* F, __global const uint* jj, float8 gx, float8 gy, float8 gz) {
  float4 p[8];
  pf_untranspose8(gx, gy, gz, (float8)(0.0f), p);
#pragma unroll
  for (uint l = 0; l < 8u; ++l) PF_REF_AT(F, jj[l]) -= p[l];
}

/* The potential's part of 8 pairs' forces on their first particles, as
 * the scale k of F = k d (d = x_i - x_j; pf_lj_force_scale8, zero beyond
 * the pair's cutoff, rc^2 q2, and where not `near`; d2 finite in every
 * lane; q2 and q the pairs' scales, PF_PAIR_Q2_8 and PF_PAIR_Q_8). Pairs on top
 * of each other get physics.cl's pf_apart direction, written back to d
 * and d2. *inv_d: 1/|d|. Shared by the
 * row loop and the pair queue, so both compute the same forces. */
float8 pf_potential8(float8* dx, float8* dy, float8* dz, float8* d2, int8 near, uint8 i_entry, uint8 jj, float8 q2,
                     float8 q, float8* inv_d) {
  const int8 tiny = near & (*d2 < PF_D_MIN * PF_D_MIN);
  if (pf_any8(tiny)) pf_apart8(dx, dy, dz, d2, tiny, jj > i_entry, (float8)(PF_D_MIN));
  /* 1/d^2 by a division, beside (not after) the square root: a shorter chain */
  *inv_d = pf_rsqrt8(*d2);
  const float8 inv_d2 = 1.0f / *d2;
  return select((float8)(0.0f), pf_lj_force_scale8(inv_d2, *inv_d, q2, q), near & (*d2 < PF_RC2 * q2));
}

/* The dashpots of the `contact` lanes (physics.cl pf_contact_damping, 8
 * lanes) added to g, from d, 1/|d| and both sides' velocities and inverse
 * masses. */
void pf_dashpots8(float8 dx, float8 dy, float8 dz, float8 inv_d, float8 uix, float8 uiy, float8 uiz, float8 imi,
                  float8 ujx, float8 ujy, float8 ujz, float8 imj, float8 q, int8 contact, float8* gx, float8* gy,
                  float8* gz) {
  const float8 nx = dx * inv_d, ny = dy * inv_d, nz = dz * inv_d;
  const float8 un = (uix - ujx) * nx + (uiy - ujy) * ny + (uiz - ujz) * nz;
  const float8 cf = select((float8)(0.0f), pf_contact_damping8(un, imi, imj, (float8)(PF_DASHPOT), q), contact);
  *gx += cf * nx;
  *gy += cf * ny;
  *gz += cf * nz;
}

/* The pairs in particle i's list, 8 entries at a time as float8 vectors.
 * Returns the force on i, with w = the overlapping pairs it counts. With
 * PF_NEWTON (each pair in one of its two particles' lists) the force on
 * each partner j is also subtracted from F[j] (Newton's third law) and
 * every listed overlap counts; without, only those with j > i. Entries
 * from `touching` on cannot touch i (pf_prune_row): their chunks skip the
 * radii and the contact code. Every chunk runs the potential, even with
 * no pair in reach (with inner lists nearly every chunk has one, and the
 * test costs more than it saves). Inlined into pair_forces: as a call it
 * spilled its constants and cost more. */
__attribute__((always_inline)) float4 pf_row_forces(uint i, float4 xi, float4 vi, __global const uint* row, uint count,
                                                    uint touching, __global const float4* X, __global const float4* V,
                                                    __global float4* F, uint8* jlo, uint8* jhi) {
  const float ri = xi.w, inv_mi = vi.w;
  float8 fx = (float8)(0.0f), fy = (float8)(0.0f), fz = (float8)(0.0f);
  int8 overlaps = (int8)(0); /* -1 per overlapping pair */
  for (uint k = 0; k < count; k += 8u) {
    const int8 lane = (int8)(0, 1, 2, 3, 4, 5, 6, 7) + (int8)((int)k);
    const int8 valid = lane < (int8)((int)count);
    /* past the count: stale indices of valid particles (the buffer starts
     * zeroed; the build pads with i), read and then masked */
    const uint8 jj = vload8(0, row + k);
    const bool may_touch = k < touching;
    float8 dx, dy, dz, rs = (float8)(0.0f);
    /* (unequal spheres: every pair's radii, for its scale) */
    pf_row_gather8(X, row + k, &dx, &dy, &dz, (PF_POLY || may_touch) ? &rs : 0);
    dx = xi.x - dx;
    dy = xi.y - dy;
    dz = xi.z - dz;
    rs += ri;
    float8 d2 = dx * dx + dy * dy + dz * dz;
    const float8 q2 = PF_PAIR_Q2_8(rs), q = PF_PAIR_Q_8(rs);
    const float8 touch2 = fmax(rs * rs, PF_CONTACT2 * q2);
    const int8 near = valid & (d2 < (may_touch ? fmax(touch2, PF_RC2 * q2) : PF_RC2 * q2));
    d2 = select((float8)(1.0f), d2, near); /* masked lanes stay finite */
    float8 inv_d;
    const float8 kf = pf_potential8(&dx, &dy, &dz, &d2, near, (uint8)(PF_ENTRY(i)), jj, q2, q, &inv_d);
    float8 gx = kf * dx, gy = kf * dy, gz = kf * dz;
    const int8 contact = near & (d2 < touch2);
    if (may_touch && pf_any8(contact)) {
      float8 vx, vy, vz, imj;
      pf_row_gather8(V, row + k, &vx, &vy, &vz, &imj);
      pf_dashpots8(dx, dy, dz, inv_d, vi.x, vi.y, vi.z, inv_mi, vx, vy, vz, imj, q, contact, &gx, &gy, &gz);
#if PF_NEWTON
      overlaps += contact & (d2 < rs * rs);
#else
      overlaps += contact & (d2 < rs * rs) & (jj > (uint8)(PF_ENTRY(i)));
#endif
    }
    fx += gx;
    fy += gy;
    fz += gz;
#if PF_NEWTON
    pf_scatter_sub8(F, row + k, gx, gy, gz);
    pf_span_add8(jlo, jhi, jj, valid);
#endif
  }
  const int4 o4 = overlaps.lo + overlaps.hi;
  const int2 o2 = o4.lo + o4.hi;
  const float4 hx = fx.lo + fx.hi, hy = fy.lo + fy.hi, hz = fz.lo + fz.hi;
  return (float4)(hx.x + hx.y + hx.z + hx.w, hy.x + hy.y + hy.z + hy.w, hz.x + hz.y + hz.z + hz.w,
                  (float)(-(o2.x + o2.y)));
}

#if PF_PAIR_QUEUE
/* The pair queue (EngineParams::pair_queue): rows are first only tested,
 * 8 entries at a time, and the entries within reach are appended with
 * their offsets (pf_queue_push); the forces are then computed 8 queued
 * pairs at a time (pf_queue_pairs8), whatever rows they came from, so that
 * short rows with few pairs in reach (purely repulsive lists) do not run
 * a whole 8-lane force batch, velocity gather and scatter for one or two
 * pairs. Both particles' forces are scattered (the i side with w = the
 * overlapping pairs counted); the j side only with PF_NEWTON. */
typedef struct {
  uint i[16], j[16]; /* the pairs' two particles as row entries (PF_ENTRY) */
  float dx[16], dy[16], dz[16], rs[16];
  uint count;
} pf_queue;

/* F at entry idx[l] (PF_ENTRY, in private memory) += (gx, gy, gz, gw).sl
 * for the 8 lanes, one read-modify-write a lane in lane order (so repeated
 * entries add up). */
void pf_scatter_add8(__global float4* F, const uint* idx, float8 gx, float8 gy, float8 gz, float8 gw) {
  float4 p[8];
  pf_untranspose8(gx, gy, gz, gw, p);
#pragma unroll
  for (uint l = 0; l < 8u; ++l) PF_REF_AT(F, idx[l]) += p[l];
}

/* The float4s of X at entries idx[0..7] (in private memory) as lane vectors. */
void pf_gather8_private(__global const float4* X, const uint* idx, float8* x, float8* y, float8* z, float8* w) {
  float4 p[8];
#pragma unroll
  for (uint l = 0; l < 8u; ++l) p[l] = PF_LOAD_AT(X, idx[l]);
  pf_transpose8(p, x, y, z, w);
}

/* The forces of the first `valid` (1..8) queued pairs, added to F (the
 * physics of pf_row_forces: pf_potential8 and pf_dashpots8). */
__attribute__((always_inline)) void pf_queue_pairs8(pf_queue* q, uint valid, __global const float4* V,
                                                   __global float4* F, uint8* jlo, uint8* jhi) {
  const int8 ok = (int8)(0, 1, 2, 3, 4, 5, 6, 7) < (int8)((int)valid);
  const uint8 ii = vload8(0, q->i), jj = vload8(0, q->j);
  float8 dx = vload8(0, q->dx), dy = vload8(0, q->dy), dz = vload8(0, q->dz);
  const float8 rs = vload8(0, q->rs);
  const float8 q2 = PF_PAIR_Q2_8(rs), qs = PF_PAIR_Q_8(rs);
  const float8 touch2 = fmax(rs * rs, PF_CONTACT2 * q2);
  float8 d2 = select((float8)(1.0f), dx * dx + dy * dy + dz * dz, ok); /* unused lanes stay finite */
  float8 inv_d;
  const float8 kf = pf_potential8(&dx, &dy, &dz, &d2, ok, ii, jj, q2, qs, &inv_d);
  float8 gx = kf * dx, gy = kf * dy, gz = kf * dz, gw = (float8)(0.0f);
  const int8 contact = ok & (d2 < touch2);
  if (pf_any8(contact)) {
    float8 vix, viy, viz, imi, vjx, vjy, vjz, imj;
    pf_gather8_private(V, q->i, &vix, &viy, &viz, &imi);
    pf_gather8_private(V, q->j, &vjx, &vjy, &vjz, &imj);
    pf_dashpots8(dx, dy, dz, inv_d, vix, viy, viz, imi, vjx, vjy, vjz, imj, qs, contact, &gx, &gy, &gz);
#if PF_NEWTON
    gw = select((float8)(0.0f), (float8)(1.0f), contact & (d2 < rs * rs));
#else
    gw = select((float8)(0.0f), (float8)(1.0f), contact & (d2 < rs * rs) & (jj > ii));
#endif
  }
  pf_scatter_add8(F, q->i, gx, gy, gz, gw);
#if PF_NEWTON
  pf_scatter_add8(F, q->j, -gx, -gy, -gz, (float8)(0.0f));
  pf_span_add8(jlo, jhi, jj, ok);
#endif
}

/* Particle i's list entries within reach, appended to the queue; each
 * full 8 are computed at once. This and pf_queue_pairs8 are inlined: as
 * calls they cost more. */
__attribute__((always_inline)) void pf_queue_push(pf_queue* q, uint i, float4 xi, __global const uint* row,
                                                 uint count, __global const float4* X, __global const float4* V,
                                                 __global float4* F, uint8* jlo, uint8* jhi) {
  for (uint k = 0; k < count; k += 8u) {
    const int8 lane = (int8)(0, 1, 2, 3, 4, 5, 6, 7) + (int8)((int)k);
    float8 dx, dy, dz, rs;
    pf_gather8(X, row + k, &dx, &dy, &dz, &rs);
    dx = xi.x - dx;
    dy = xi.y - dy;
    dz = xi.z - dz;
    rs += xi.w;
    const float8 d2 = dx * dx + dy * dy + dz * dz;
    const float8 q2 = PF_PAIR_Q2_8(rs);
    const int8 near = (lane < (int8)((int)count)) & (d2 < fmax(fmax(rs * rs, PF_CONTACT2 * q2), PF_RC2 * q2));
    if (!pf_any8(near)) continue;
    const uint at = q->count;
#if defined(PF_MASK8)
    const uchar mask = PF_MASK8(near);
    vstore8((uint8)(PF_ENTRY(i)), 0, q->i + at);
    vstore8(PF_PACK8U(vload8(0, row + k), (uint8)(0u), mask), 0, q->j + at);
    vstore8(PF_PACK8F(dx, (float8)(0.0f), mask), 0, q->dx + at);
    vstore8(PF_PACK8F(dy, (float8)(0.0f), mask), 0, q->dy + at);
    vstore8(PF_PACK8F(dz, (float8)(0.0f), mask), 0, q->dz + at);
    vstore8(PF_PACK8F(rs, (float8)(0.0f), mask), 0, q->rs + at);
    q->count = at + popcount((uint)mask);
#else
    int m[8];
    float ox[8], oy[8], oz[8], ors[8];
    vstore8(near, 0, m);
    vstore8(dx, 0, ox);
    vstore8(dy, 0, oy);
    vstore8(dz, 0, oz);
    vstore8(rs, 0, ors);
    uint c = at;
    for (uint l = 0; l < 8u; ++l) {
      if (m[l] == 0) continue;
      q->i[c] = PF_ENTRY(i);
      q->j[c] = row[k + l];
      q->dx[c] = ox[l];
      q->dy[c] = oy[l];
      q->dz[c] = oz[l];
      q->rs[c] = ors[l];
      ++c;
    }
    q->count = c;
#endif
    if (q->count >= 8u) { /* a full batch; the rest (fewer than 8) moves to the front */
      pf_queue_pairs8(q, 8u, V, F, jlo, jhi);
      q->count -= 8u;
      vstore8(vload8(1, q->i), 0, q->i);
      vstore8(vload8(1, q->j), 0, q->j);
      vstore8(vload8(1, q->dx), 0, q->dx);
      vstore8(vload8(1, q->dy), 0, q->dy);
      vstore8(vload8(1, q->dz), 0, q->dz);
      vstore8(vload8(1, q->rs), 0, q->rs);
    }
  }
}
#endif

/* A list row being rebuilt (pair_forces): where the rows go and what a
 * rebuild records of each particle. */
typedef struct {
  __global uint* list;
  __global uint* list_count;
  __global uint2* spans;
  __global float4* XREF;
  __global uint* build_bits;
  uint next_row; /* with PF_NEWTON, the next packed row's first word */
} pf_rebuild;

/* list_count's mark of a row not yet rebuilt on a step that rebuilds */
#define PF_UNBUILT UINT_MAX

/* Rebuilds particle i's row (at level-0 cell c) from the stencil of its cell. */
void pf_rebuild_row(pf_rebuild* b, uint i, float4 xi, int4 c, const pf_stencil* st, __global const uint* counts,
                    __global const float* slots, int4 cell_dims, uint level_mask) {
#if PF_NEWTON
  __global uint* row = b->list + b->next_row;
#else
  __global uint* row = PF_ROW(b->list, i);
#endif
  uint bits = 0u;
  const uint count = pf_build_list(i, xi, st, counts, slots, c, cell_dims, level_mask, row, &bits);
  b->list_count[i] = count;
#if PF_NEWTON
  const uint room = min(count + PF_ROW_SLACK, PF_LIST_CAP);
  b->spans[i] = (uint2)(b->next_row, room);
  b->next_row += room;
#endif
  b->XREF[i] = xi;
  b->build_bits[i] = bits;
}

/* Rebuilds the rows of the particles of st's cell in (i, end) from st, so
 * that the stencil is gathered once a cell, not once for each run of the
 * cell in index order (after Engine::sort_by_cells the particles stray
 * from their cells' runs within a few steps; measured 1.7 particles a
 * gather in pass 1 at 1e5, ~6 a cell). A row is the same whoever builds
 * it, and the forces still sum in index order. */
void pf_rebuild_cell_mates(pf_rebuild* b, uint i, uint end, const pf_stencil* st, __global const float4* X,
                           __global const uint* counts, __global const float* slots, float4 cell_origin,
                           float4 cell_inv, int4 cell_dims, uint level_mask, float ri) {
  if (pf_no_block(slots, st->cell)) return;
#if PF_LEVELS > 1
  const uint cap = pf_level_at(cell_dims, pf_level_of(ri)).cap; /* (the cell's level's) */
#else
  const uint cap = PF_CELL_CAP;
#endif
  const uint m = min(counts[st->cell], cap); /* (the overflowed rest: each builds at its own turn) */
  __global const float* block = slots + pf_block_at(slots, st->cell);
  for (uint k = 0; k < m; ++k) {
    const uint j = as_uint(block[PF_SLOT(k, 4u)]);
    if (j <= i || j >= end) continue;
    const float4 xj = X[j];
    pf_rebuild_row(b, j, xj, pf_cell_of(xj, cell_origin, cell_inv, cell_dims), st, counts, slots, cell_dims,
                   level_mask);
  }
}

/* inner_count's mark of a particle whose pair loop reads its whole list
 * (no room left for its inner list in its block's share) */
#define PF_FULL_ROW UINT_MAX
/* For tests: 1 reads every whole list, as if no block had room */
#ifndef PF_INNER_FULL_ROWS
#define PF_INNER_FULL_ROWS 0
#endif

/* The pair forces of a step on CPU devices, before `advance` (which adds
 * them up). Work-group w of W (one work-item each) takes particles
 * [w B, (w + 1) B), B = ceil(n / W), in order. With PF_NEWTON it sums
 * forces into its own buffer F + w * force_stride only (a few work-items,
 * one per core), so no two work-items write one word and the sums come out
 * the same on every run, and records in force_spans[w] the particles whose
 * forces it changed there (its block and the partners it wrote to, mostly
 * just past the block), so that `advance` reads and clears only those of
 * the W buffers; without, it writes its particles' forces into F.
 * On the steps that rebuild the lists, each particle's list is rebuilt
 * before its forces, with those of its cell's later particles in the block
 * (pf_rebuild_cell_mates); build_bits keeps the overflow bit for `advance`. Rows
 * filled by birth_linked's atomics (at most 4 newcomers, in sort_rows)
 * are sorted first, so that forces sum in one order. */
__kernel __attribute__((reqd_work_group_size(1, 1, 1))) void pair_forces(
    __global const float4* X, __global const float4* V, __global const uint* counts, __global const float* slots,
    const uint cell_base, const float4 cell_origin, const float4 cell_inv, const int4 cell_dims, const uint n,
    __global uint* list, __global uint* list_count, __global float4* XREF, __global uint* build_bits,
    __global const uint* request, const uint request_read, const uint force_rebuild, __global float4* F,
    const uint force_stride, const int4 sort_rows, __global uint* inner_list, __global uint2* inner_count,
    __global float4* XPRUNE, __global uint2* spans, __global uint2* force_spans, const uint level_mask) {
  const uint w = get_global_id(0), per = (n + get_global_size(0) - 1u) / get_global_size(0);
  const uint end = min(n, (w + 1u) * per);
  __global float4* Fw = PF_NEWTON ? F + (size_t)w * force_stride : F;
  /* the partners' entries (PF_ENTRY) this writes forces to: lowest, highest */
  uint8 jlo = (uint8)(UINT_MAX), jhi = (uint8)(0u);
  const uint requested = request[request_read];
  const uint rebuild = force_rebuild || (requested & PF_REQUEST_REBUILD);
#if PF_INNER
  const uint prune = rebuild || (requested & PF_REQUEST_PRUNE);
#endif
#if PF_PAIR_QUEUE
  pf_queue q;
  q.count = 0u;
#endif
  /* the list build's candidates (on the steps that rebuild): the stencils
   * of the last two cells, so that a particle that has moved out of its
   * run's cell (the order since the last sort_by_cells decays) costs one
   * gather, not two */
  pf_stencil st[2];
  st[0].cell = st[1].cell = UINT_MAX;
  uint newest = 0u;
#if PF_INNER
  /* The block's inner lists lie packed one after the other from the
   * block's first PF_INNER_CAP words a particle on (a pruning writes them
   * all, and the count and so the blocks cannot change before the next:
   * births and removals make the next step prune), so the pair loop
   * streams them. */
  __global uint* inner_next = inner_list + (size_t)(w * per) * PF_INNER_CAP;
  __global const uint* const inner_end = inner_list + (size_t)end * PF_INNER_CAP;
#endif
  /* a rebuild packs the block's rows from its first PF_ROW_STRIDE words on */
  pf_rebuild b = {list, list_count, spans, XREF, build_bits, w * per * PF_ROW_STRIDE};
  if (rebuild)
    for (uint i = w * per; i < end; ++i) list_count[i] = PF_UNBUILT;
  for (uint i = w * per; i < end; ++i) {
    const float4 xi = X[i];
    uint count, touching; /* touching: entries that may touch i come first (pf_prune_row) */
    if (rebuild && list_count[i] == PF_UNBUILT) {
      const int4 c = pf_cell_of(xi, cell_origin, cell_inv, cell_dims);
      const uint cell = pf_stencil_key(xi.w, c, cell_dims);
      if (st[newest].cell != cell) {
        newest = 1u - newest;
        if (st[newest].cell != cell)
          pf_stencil_gather(&st[newest], counts + cell_base, slots, c, xi.w, cell_dims, cell_inv.x, level_mask);
      }
      pf_rebuild_row(&b, i, xi, c, &st[newest], counts + cell_base, slots, cell_dims, level_mask);
      pf_rebuild_cell_mates(&b, i, end, &st[newest], X, counts + cell_base, slots, cell_origin, cell_inv, cell_dims,
                            level_mask, xi.w);
    }
    __global uint* row = PF_LIST_ROW(list, spans, i);
    count = min(list_count[i], PF_LIST_CAP);
    if (!rebuild) {
      const int4 newcomer = (int4)((int)i) == sort_rows; /* (PoCL makes four branches of any()) */
      if ((newcomer.x | newcomer.y | newcomer.z | newcomer.w) != 0) pf_sort_row(row, count);
    }
#if PF_INNER
    /* the pairs read the inner list, pruned from the list when due; the
     * list itself where the block's room left might not take it (its
     * count bounds the inner list's; PF_INNER_CAP a particle is a bound as
     * the list's capacity is, so this is for safety, not seen) */
    if (prune) {
      if (!PF_INNER_FULL_ROWS && inner_next + count + 8u <= inner_end) {
        count = pf_prune_row(i, xi, row, count, X, inner_next, &touching);
        inner_count[i] = (uint2)(count, touching);
        row = inner_next;
        inner_next += count;
      } else {
        inner_count[i] = (uint2)(PF_FULL_ROW, 0u);
        touching = count;
      }
      XPRUNE[i] = xi;
    } else {
      const uint2 counts = inner_count[i];
      if (counts.x == PF_FULL_ROW) {
        touching = count;
      } else {
        count = counts.x;
        touching = counts.y;
        row = inner_next;
        inner_next += count;
      }
    }
#else
    touching = count;
#endif
#if PF_PAIR_QUEUE
    pf_queue_push(&q, i, xi, row, count, X, V, Fw, &jlo, &jhi);
#else
    Fw[i] += pf_row_forces(i, xi, V[i], row, count, touching, X, V, Fw, &jlo, &jhi);
#endif
  }
#if PF_PAIR_QUEUE
  if (q.count > 0u) { /* the last, partial batch: its unused lanes name particles of the block, with zero force */
    for (uint l = q.count; l < 8u; ++l) {
      q.i[l] = q.i[0];
      q.j[l] = q.i[0];
      q.dx[l] = q.dy[l] = q.dz[l] = q.rs[l] = 0.0f;
    }
    pf_queue_pairs8(&q, q.count, V, Fw, &jlo, &jhi);
  }
#endif
#if PF_NEWTON
  /* the particles whose entries in F_w this may have changed: the block
   * and the partners it wrote to (`advance` reads and clears only those) */
  const uint4 lo4 = min(jlo.lo, jlo.hi), hi4 = max(jhi.lo, jhi.hi);
  const uint2 lo2 = min(lo4.lo, lo4.hi), hi2 = max(hi4.lo, hi4.hi);
  const uint lo = min(lo2.x, lo2.y), hi = max(hi2.x, hi2.y), first = min(w * per, end);
  force_spans[w] = (uint2)(min(first, lo >> 4), max(end, lo > hi ? 0u : (hi >> 4) + 1u));
#endif
}
