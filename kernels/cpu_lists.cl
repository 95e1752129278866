/* cpu_lists.cl: the CPU form's neighbour lists (after cells.cl and
 * x86.cl): the rows' layout, the list build from a cell's stencil, and
 * dynamic pruning into inner lists.
 *
 * Each list row is contiguous (PF_LIST_CAP entries), read 8 entries at a
 * time as float8 vectors. PF_ROW(list, i) is particle i's row, PF_AT(row,
 * k) its entry k; capacities are multiples of 8 entries. */
#define PF_ROW(list, i) ((list) + (size_t)(i) * PF_LIST_CAP)

/* physics.cl's pair scales at 8 lanes, and PF_PAIR_Q2's and PF_PAIR_Q's 8-lane forms. */
PF_DEFINE_PAIR_SCALE2(pf_pair_scale2_8, float8)
PF_DEFINE_PAIR_SCALE(pf_pair_scale_8, float8)
#if PF_POLY
#define PF_PAIR_Q2_8(rs) pf_pair_scale2_8(rs, PF_RS_REF, PF_INV_RS_REF2)
#define PF_PAIR_Q_8(rs) pf_pair_scale_8(rs, PF_RS_REF, PF_INV_RS_REF)
#else
#define PF_PAIR_Q2_8(rs) ((float8)(1.0f))
#define PF_PAIR_Q_8(rs) ((float8)(1.0f))
#endif
#define PF_AT(row, k) ((row)[k])

/* With PF_NEWTON the rows of each block are packed one after the other
 * at a rebuild, each with PF_ROW_SLACK entries of room for linked births
 * after it (pair_forces): spans[i] = (the row's first word, its room, at
 * most PF_LIST_CAP), and PF_LIST_ROW is the row; without, PF_ROW. A
 * block's rows fit in its PF_ROW_STRIDE words a particle. */
#define PF_ROW_SLACK 8u
#define PF_ROW_STRIDE (PF_LIST_CAP + PF_ROW_SLACK)
#if PF_NEWTON
#define PF_LIST_ROW(list, spans, i) ((list) + (spans)[i].x)
#else
#define PF_LIST_ROW(list, spans, i) PF_ROW(list, i)
#endif

/* A row entry names neighbour j by the byte offset of its float4 (16 j,
 * so at most 2^27 particles: the AVX-512 gathers read the offsets as
 * signed), which the pair loop adds to X, V or F as it is (x86 scales an
 * index by at most 8: a plain index costs a shift a lane). PF_LOAD_AT /
 * PF_REF_AT: the float4 of an entry, read-only or to update. */
#define PF_ENTRY(j) ((j) << 4)
#define PF_LOAD_AT(base, e) (*(__global const float4*)((__global const uchar*)(base) + (e)))
#define PF_REF_AT(base, e) (*(__global float4*)((__global uchar*)(base) + (e)))

/* The float4s of X at row entries row[0..7] (PF_ENTRY) as lane vectors.
 * The entries are read from memory as scalars: taking them out of a
 * vector costs more instructions. */
void pf_gather8(__global const float4* X, __global const uint* row, float8* x, float8* y, float8* z, float8* w) {
  float4 p[8];
#pragma unroll
  for (uint l = 0; l < 8u; ++l) p[l] = PF_LOAD_AT(X, row[l]);
  pf_transpose8(p, x, y, z, w);
}

#if defined(PF_X86_AVX512)
/* One float of the float4s at 8 row entries (byte offsets, so scale 1),
 * `offset` bytes into each, by a hardware gather. The builtin takes a
 * private pointer; PoCL on a CPU has one flat address space, so the
 * global address passes through an integer. */
float8 pf_gather_component8(__global const float4* X, int8 entries, uint offset) {
  return __builtin_ia32_gather3siv8sf((float8)(0.0f), (const void*)((size_t)X + offset), entries, (uchar)0xff, 1);
}
#endif

/* pf_gather8 for the row loop (pf_row_forces): with
 * AVX-512, hardware gathers of one component each. They take fewer
 * instructions than the loads and transposes, and long rows hide their
 * latency. The pair queue's short rows do not, so it keeps pf_gather8
 * (measured: see the commit messages and bench/results). w: 0 where the
 * caller needs no w. */
void pf_row_gather8(__global const float4* X, __global const uint* row, float8* x, float8* y, float8* z, float8* w) {
#if defined(PF_X86_AVX512)
  const int8 e = vload8(0, (__global const int*)row);
  *x = pf_gather_component8(X, e, 0u);
  *y = pf_gather_component8(X, e, 4u);
  *z = pf_gather_component8(X, e, 8u);
  if (w) *w = pf_gather_component8(X, e, 12u);
#else
  float8 unused;
  pf_gather8(X, row, x, y, z, w ? w : &unused);
#endif
}
/* Sorts a list row (or a piece of one) by index (see pf_build_list). */
void pf_sort_row(__global uint* row, uint count) {
  for (uint k = 1; k < count; ++k) {
    const uint v = PF_AT(row, k);
    uint m = k;
    for (; m > 0 && PF_AT(row, m - 1) > v; --m) PF_AT(row, m) = PF_AT(row, m - 1);
    PF_AT(row, m) = v;
  }
}

/* The entries of the lanes where `hit` is set, in lane order, stored
 * from row[found] on (none at or past PF_LIST_CAP). With AVX-512 they are
 * packed in a register and stored as one vector, padded with `pad` (an
 * entry of the row's own particle: a row holds entries only). */
void pf_store_hits8(__global uint* row, uint found, uint8 entries, int8 hit, uint pad) {
#if defined(PF_MASK8)
  if (found + 8u <= PF_LIST_CAP) {
    vstore8(PF_PACK8U(entries, (uint8)(pad), PF_MASK8(hit)), 0, row + found);
    return;
  }
#endif
  uint e[8];
  int h[8];
  vstore8(entries, 0, e);
  vstore8(hit, 0, h);
  for (uint l = 0; l < 8u; ++l) {
    if (h[l] == 0) continue;
    if (found < PF_LIST_CAP) PF_AT(row, found) = e[l];
    ++found;
  }
}

/* pf_store_hits8 into private memory (room for 8 words from `found` on). */
void pf_store_hits8_private(uint* row, uint found, uint8 entries, int8 hit, uint pad) {
#if defined(PF_MASK8)
  vstore8(PF_PACK8U(entries, (uint8)(pad), PF_MASK8(hit)), 0, row + found);
#else
  uint e[8];
  int h[8];
  vstore8(entries, 0, e);
  vstore8(hit, 0, h);
  for (uint l = 0; l < 8u; ++l)
    if (h[l] != 0) row[found++] = e[l];
#endif
}

/* Dynamic pruning (EngineParams::inner_lists): particle i's inner list,
 * the entries of its list within PF_RI (the reach plus the inner skin) of
 * it now, written to `inner`; returns their count. A particle that then
 * moves half the inner skin makes the next step prune again, so no pair
 * left out comes within reach before that, and no pair closes in by more
 * than the inner skin. So the entries come in two runs, each in the
 * list's order: first those that may touch i before the next pruning
 * (closer than their touch distance max(r_i + r_j, rest) plus the inner
 * skin; *touching: how many), then those that cannot. pf_row_forces runs
 * the contact code only on the first run's chunks: its branch on contacts
 * no longer goes one way or the other by chance. */
uint pf_prune_row(uint i, float4 xi, __global const uint* row, uint count, __global const float4* X,
                  __global uint* inner, uint* touching) {
  uint near_count = 0u, apart_count = 0u;
  uint apart[PF_LIST_CAP + 8u];
  for (uint k = 0; k < count; k += 8u) {
    float8 dx, dy, dz, rs;
    pf_gather8(X, row + k, &dx, &dy, &dz, &rs); /* (here faster than the hardware gathers) */
    dx = xi.x - dx;
    dy = xi.y - dy;
    dz = xi.z - dz;
    const float8 d2 = dx * dx + dy * dy + dz * dz;
    const int8 lane = (int8)(0, 1, 2, 3, 4, 5, 6, 7) + (int8)((int)k);
    int8 within = (lane < (int8)((int)count)) & (d2 < PF_RI2);
    /* (1 + 1e-5: the rounding of the square, on the safe side) */
#if PF_POLY
    /* the pair's own reach: its scaled cutoff or contact distance, plus the inner skin */
    const float8 q = (rs + xi.w) * PF_INV_RS_REF;
    const float8 pair_reach = fmax(q * PF_REACH_REF, rs + xi.w) + PF_INNER_SKIN;
    within &= d2 < pair_reach * pair_reach * 1.00001f;
    const float8 reach = fmax(rs + xi.w, PF_CONTACT * q) + PF_INNER_SKIN;
#else
    const float8 reach = fmax(rs + xi.w, PF_CONTACT) + PF_INNER_SKIN;
#endif
    const int8 near = within & (d2 < reach * reach * 1.00001f);
    const uint8 entries = vload8(0, row + k);
    pf_store_hits8(inner, near_count, entries, near, PF_ENTRY(i));
    near_count += pf_count8(near);
    pf_store_hits8_private(apart, apart_count, entries, within & ~near, PF_ENTRY(i));
    apart_count += pf_count8(within & ~near);
  }
  *touching = near_count;
  __global uint* rest = inner + near_count;
#if defined(PF_MASK8)
  /* whole chunks (a row has 8 words of room past its end), padded with i
   * as the list's rows are: the pair loop reads the words past the count */
  vstore8((uint8)(PF_ENTRY(i)), 0, apart + apart_count);
  for (uint k = 0; k < apart_count; k += 8u) vstore8(vload8(0, apart + k), 0, rest + k);
#else
  for (uint k = 0; k < apart_count; ++k) rest[k] = apart[k];
#endif
  return near_count + apart_count;
}

/* The candidates of the CPU form's list builds for the particles of one
 * cell: the particles of the cells of its stencil, copied once for all of
 * the cell's particles in a pair_forces block (pf_rebuild_cell_mates) into
 * contiguous arrays, so that each particle's build is one pass of 8-lane
 * loads over them. With PF_NEWTON the stencil
 * is half: the cell itself (its particles first, [0, own), partners j > i
 * only) and the 13 cells after it in (z, y, x) order, so a pair of cells
 * meets once; without, all 27 in (z, y, x) order. Each cell's particles are
 * sorted by index (the cells hold them in the order of their atomic
 * insertions, which varies run to run on a multi-threaded device), so the
 * rows come out in one order and the same input gives the same particles. */
#if PF_NEWTON
#define PF_STENCIL_CELLS 14u
#else
#define PF_STENCIL_CELLS 27u
#endif
#if PF_LEVELS > 1
/* Cell levels (cells.cl): the stencil holds the own level's cells as
 * above, then the 27 around the particle in each level above (partners
 * larger than the cell's particles: with PF_NEWTON the smaller of a pair
 * of two levels lists it). Without PF_NEWTON the levels below (many small
 * partners of a large sphere) are read from the cells by pf_build_list. */
#define PF_STENCIL_CAP                                                                                  \
  (PF_STENCIL_CELLS * (PF_CELL_CAP > PF_CELL_CAP_UP ? PF_CELL_CAP : PF_CELL_CAP_UP) +                   \
   27u * (PF_LEVELS - 1u) * PF_CELL_CAP_UP + 16u) /* (+ 8 of padding before the levels above) */
#else
#define PF_STENCIL_CAP (PF_STENCIL_CELLS * PF_CELL_CAP + 8u) /* 8 lanes of slack past the last */
#endif
typedef struct {
  float x[PF_STENCIL_CAP], y[PF_STENCIL_CAP], z[PF_STENCIL_CAP];
#if PF_POLY
  float r[PF_STENCIL_CAP]; /* radii (unequal spheres: each pair's own reach, PF_LISTED) */
#endif
  uint e[PF_STENCIL_CAP]; /* as row entries (PF_ENTRY) */
  uint count, own;        /* candidates; the cell's own ones ([0, own)) */
#if PF_LEVELS > 1
  uint upper;             /* the levels above from here on (a multiple of 8; unsorted) */
#endif
  uint cell;              /* whose stencil (UINT_MAX: none yet) */
  uint bits;              /* the overflow bit, where a cell of the stencil overflowed */
} pf_stencil;

/* Copies the listed particles of a cell (its count word counts[cell], its
 * slots `block`, `cap` of them) to the end of st's candidates, in index order. */
void pf_stencil_add_block(pf_stencil* st, __global const uint* counts, uint cell, __global const float* block,
                          uint cap, bool sorted) {
  const uint m = pf_cell_listed_cap(counts, cell, cap, &st->bits), at = st->count;
  /* whether the cell's entries are out of index order (most cells are in
   * order: insert_cells's work-items fill them from runs of the particles) */
  int8 disorder = (int8)(0);
  uint before = 0u; /* the last entry of the chunk before */
  for (uint k = 0; k < m; k += 8u) { /* whole chunks; the lanes past m are overwritten or never read */
    __global const float* chunk = block + 5u * k;
    vstore8(vload8(0, chunk), 0, st->x + at + k);
    vstore8(vload8(1, chunk), 0, st->y + at + k);
    vstore8(vload8(2, chunk), 0, st->z + at + k);
#if PF_POLY
    vstore8(vload8(3, chunk), 0, st->r + at + k);
#endif
    const uint8 e = as_uint8(vload8(4, chunk));
    vstore8(e << 4u, 0, st->e + at + k);
    const uint8 previous = (uint8)(before, e.s0, e.s1, e.s2, e.s3, e.s4, e.s5, e.s6);
    const uint8 lane = (uint8)(0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u) + (uint8)(k);
    disorder |= (previous > e) & (lane < (uint8)(m)) & (lane > (uint8)(0u));
    before = e.s7;
  }
  const bool sort = sorted && any(disorder);
  for (uint k = sort ? at + 1u : at + m; k < at + m; ++k) { /* insertion sort: the cells are nearly in order */
    const uint e = st->e[k];
    const float x = st->x[k], y = st->y[k], z = st->z[k];
#if PF_POLY
    const float r = st->r[k];
#endif
    uint q = k;
    for (; q > at && st->e[q - 1u] > e; --q) {
      st->e[q] = st->e[q - 1u];
      st->x[q] = st->x[q - 1u];
      st->y[q] = st->y[q - 1u];
      st->z[q] = st->z[q - 1u];
#if PF_POLY
      st->r[q] = st->r[q - 1u];
#endif
    }
    st->e[q] = e;
    st->x[q] = x;
    st->y[q] = y;
    st->z[q] = z;
#if PF_POLY
    st->r[q] = r;
#endif
  }
  st->count = at + m;
}

/* Copies level-0 cell `cell`'s listed particles to the end of st's candidates, in index order. */
void pf_stencil_add(pf_stencil* st, __global const uint* counts, __global const float* slots, uint cell) {
  pf_stencil_add_block(st, counts, cell, slots + pf_block_at(slots, cell), PF_CELL_CAP, true);
}

#if PF_LEVELS > 1
/* Which stencil a particle of radius r in level-0 cell c takes: its cell
 * in its own level (numbered over all levels). */
uint pf_stencil_key(float r, int4 c, int4 cell_dims) {
  const uint own = pf_level_of(r);
  const pf_level g = pf_level_at(cell_dims, own);
  return g.first + pf_cell_index(c >> (int4)((int)own), g.dims);
}

/* Copies the cells [lo, hi] of level grid g, in (z, y, x) order, each sorted or not. */
void pf_stencil_add_span(pf_stencil* st, __global const uint* counts, __global const float* slots, pf_level g,
                         int4 lo, int4 hi, bool sorted) {
  for (int cz = lo.z; cz <= hi.z; ++cz)
    for (int cy = lo.y; cy <= hi.y; ++cy)
      for (int cx = lo.x; cx <= hi.x; ++cx) {
        const uint in_level = pf_cell_index((int4)(cx, cy, cz, 0), g.dims);
        pf_stencil_add_block(st, counts, g.first + in_level, slots + pf_block_at(slots, g.first + in_level), g.cap, sorted);
      }
}

/* st becomes the stencil of a particle of radius r in level-0 cell c0
 * (cell levels: see PF_STENCIL_CAP). */
void pf_stencil_gather_levels(pf_stencil* st, __global const uint* counts, __global const float* slots, int4 c0,
                              float r, int4 cell_dims, float cell_inv, uint level_mask) {
  st->count = 0u;
  st->bits = 0u;
  const uint own = pf_level_of(r);
  const pf_level g = pf_level_at(cell_dims, own);
  const int4 c = c0 >> (int4)((int)own);
  st->cell = g.first + pf_cell_index(c, g.dims);
  if (pf_no_block(slots, st->cell)) st->bits |= PF_OVERFLOW_BIT; /* a sphere where none can be: not listed */
  const int4 lo = max(c - (int4)(1), (int4)(0)), hi = min(c + (int4)(1), g.dims - (int4)(1));
#if PF_NEWTON
  pf_stencil_add_block(st, counts, st->cell, slots + pf_block_at(slots, st->cell), g.cap, true);
  st->own = st->count;
  for (int cz = c.z; cz <= hi.z; ++cz)
    for (int cy = cz == c.z ? c.y : lo.y; cy <= hi.y; ++cy)
      for (int cx = cz == c.z && cy == c.y ? c.x + 1 : lo.x; cx <= hi.x; ++cx) {
        const uint in_level = pf_cell_index((int4)(cx, cy, cz, 0), g.dims);
        pf_stencil_add_block(st, counts, g.first + in_level, slots + pf_block_at(slots, g.first + in_level), g.cap, true);
      }
#else
  st->own = 0u;
  pf_stencil_add_span(st, counts, slots, g, lo, hi, true);
#endif
  /* The levels above start at a multiple of 8, after candidates too far
   * to list, and are not sorted: a small sphere's run of its cell is
   * short (its cells are small), so it would sort many large candidates
   * for each of it; pf_build_list sorts the few it lists instead. */
  while (st->count % 8u != 0u) {
    st->x[st->count] = st->y[st->count] = st->z[st->count] = 1e30f; /* (d^2 overflows to infinity: never listed) */
    st->r[st->count] = 0.0f;
    st->e[st->count] = 0u;
    ++st->count;
  }
  st->upper = st->count;
  /* the levels above: their cells within the reach of the two levels'
   * largest pair from the cell's box (in level-0 cells [c 2^own, (c + 1)
   * 2^own); a particle outside the grid, clamped into it, is only farther
   * from the others), not all 27: a small sphere reaches a large one's
   * cells less far than two large ones do */
  const float4 box_lo = convert_float4(c * (int4)(1 << own));
  const float4 box_hi = convert_float4((c + (int4)(1)) * (int4)(1 << own));
  for (uint level = own + 1u; level < PF_LEVELS; ++level) {
    if ((level_mask & (1u << level)) == 0u) continue; /* no particle was ever of that level */
    const pf_level up = pf_level_at(cell_dims, level);
    const float reach = 1.0001f * cell_inv * PF_PAIR_REACH(PF_LEVEL_R0 * (float)((1u << own) + (1u << level)));
    const float to_level = 1.0f / (float)(1u << level);
    int4 ulo, uhi; /* (within the 27, which suffice: at most 27 cells a level in the stencil) */
    pf_level_span(c, own, level, up.dims, &ulo, &uhi);
    ulo = max(convert_int4_rtn((box_lo - reach) * to_level), ulo);
    uhi = min(convert_int4_rtn((box_hi + reach) * to_level), uhi);
    pf_stencil_add_span(st, counts, slots, up, ulo, uhi, false);
  }
}
#else
uint pf_stencil_key(float r, int4 c, int4 cell_dims) { return pf_cell_index(c, cell_dims); }
#endif

/* st becomes the stencil of a particle of radius r in the cell at
 * coordinates c (cell_inv: 1 / level 0's cell edge; level_mask: the cell
 * levels that may hold particles, a bit each, Engine's). */
void pf_stencil_gather(pf_stencil* st, __global const uint* counts, __global const float* slots, int4 c, float r,
                       int4 cell_dims, float cell_inv, uint level_mask) {
#if PF_LEVELS > 1
  pf_stencil_gather_levels(st, counts, slots, c, r, cell_dims, cell_inv, level_mask);
  return;
#endif
  st->count = 0u;
  st->bits = 0u;
  st->cell = pf_cell_index(c, cell_dims);
  if (pf_no_block(slots, st->cell)) st->bits |= PF_OVERFLOW_BIT; /* a sphere where none can be: not listed */
  const int4 lo = max(c - (int4)(1), (int4)(0)), hi = min(c + (int4)(1), cell_dims - (int4)(1));
#if PF_NEWTON
  pf_stencil_add(st, counts, slots, st->cell);
  st->own = st->count;
  for (int cz = c.z; cz <= hi.z; ++cz)
    for (int cy = cz == c.z ? c.y : lo.y; cy <= hi.y; ++cy)
      for (int cx = cz == c.z && cy == c.y ? c.x + 1 : lo.x; cx <= hi.x; ++cx)
        pf_stencil_add(st, counts, slots, pf_cell_index((int4)(cx, cy, cz, 0), cell_dims));
#else
  st->own = 0u;
  for (int cz = lo.z; cz <= hi.z; ++cz)
    for (int cy = lo.y; cy <= hi.y; ++cy)
      for (int cx = lo.x; cx <= hi.x; ++cx)
        pf_stencil_add(st, counts, slots, pf_cell_index((int4)(cx, cy, cz, 0), cell_dims));
#endif
}

#if PF_LEVELS > 1 && !PF_NEWTON
/* Lists particle i's partners of the levels below its own (without
 * PF_NEWTON a large sphere lists its small partners too) from the cells
 * under its stencil, after the `found` entries of its row, sorted by index
 * (the cells hold them in the order of their atomic insertions). Returns
 * the new count (the overflow bit in *bits past PF_LIST_CAP). */
uint pf_list_levels_below(uint i, float4 xi, __global const uint* counts, __global const float* slots, int4 c0,
                          int4 cell_dims, uint level_mask, __global uint* row, uint found, uint* bits) {
  const uint own = pf_level_of(xi.w), first = found;
  const int4 c = c0 >> (int4)((int)own);
  for (uint level = 0u; level < own; ++level) {
    if ((level_mask & (1u << level)) == 0u) continue; /* no particle was ever of that level */
    const pf_level g = pf_level_at(cell_dims, level);
    int4 lo, hi;
    pf_level_span(c, own, level, g.dims, &lo, &hi);
    for (int cz = lo.z; cz <= hi.z; ++cz)
      for (int cy = lo.y; cy <= hi.y; ++cy)
        for (int cx = lo.x; cx <= hi.x; ++cx) {
          const uint in_level = pf_cell_index((int4)(cx, cy, cz, 0), g.dims);
          const uint m = pf_cell_listed_cap(counts, g.first + in_level, g.cap, bits);
          __global const float* block = slots + pf_block_at(slots, g.first + in_level);
          for (uint k = 0; k < m; ++k) {
            const float dx = xi.x - block[PF_SLOT(k, 0u)], dy = xi.y - block[PF_SLOT(k, 1u)];
            const float dz = xi.z - block[PF_SLOT(k, 2u)];
            if (!PF_LISTED(dx * dx + dy * dy + dz * dz, xi.w + block[PF_SLOT(k, 3u)])) continue;
            if (found < PF_LIST_CAP) PF_AT(row, found) = PF_ENTRY(as_uint(block[PF_SLOT(k, 4u)]));
            ++found;
          }
        }
  }
  if (found > PF_LIST_CAP) *bits |= PF_OVERFLOW_BIT;
  const uint from = min(first, PF_LIST_CAP);
  pf_sort_row(row + from, min(found, PF_LIST_CAP) - from);
  return found;
}
#endif

/* Rebuilds particle i's neighbour list from its cell's stencil: the
 * candidates j != i with |x_i - x_j|^2 < PF_RL2 (unequal spheres: and
 * their own pair's reach, PF_LISTED; with PF_NEWTON, of the
 * cell's own particles only those with j > i), in the stencil's order.
 * Returns the count (capped at PF_LIST_CAP; more set the overflow bit in
 * *bits, as does a stencil cell that overflowed). */
uint pf_build_list(uint i, float4 xi, const pf_stencil* st, __global const uint* counts, __global const float* slots,
                   int4 c, int4 cell_dims, uint level_mask, __global uint* row, uint* bits) {
  uint found = 0u;
  const uint8 ei = (uint8)(PF_ENTRY(i));
#if PF_LEVELS > 1
  uint found_own = 0u; /* the entries before the levels above */
#endif
  for (uint k = 0; k < st->count; k += 8u) {
#if PF_LEVELS > 1
    if (k == st->upper) found_own = found;
#endif
    const float8 dx = xi.x - vload8(0, st->x + k), dy = xi.y - vload8(0, st->y + k), dz = xi.z - vload8(0, st->z + k);
    const uint8 e = vload8(0, st->e + k);
    const uint8 lane = (uint8)(0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u) + (uint8)(k);
#if PF_NEWTON
    const int8 partner = lane >= (uint8)(st->own) | e > ei;
#else
    const int8 partner = e != ei;
#endif
#if PF_POLY
    const float8 d2 = dx * dx + dy * dy + dz * dz, rs = xi.w + vload8(0, st->r + k);
    const int8 near = (lane < (uint8)(st->count)) & partner & PF_LISTED(d2, rs);
#else
    const int8 near = (lane < (uint8)(st->count)) & partner & (dx * dx + dy * dy + dz * dz < PF_RL2);
#endif
    /* no branch on whether any lane hit: at rc = 2.5 sigma about half the
     * chunks do, at random, and the mispredictions cost more than a store */
    pf_store_hits8(row, found, e, near, PF_ENTRY(i));
    found += pf_count8(near);
  }
#if PF_LEVELS > 1
  if (st->upper >= st->count) found_own = found;
  {
    const uint from = min(found_own, PF_LIST_CAP); /* the levels above' entries in index order */
    pf_sort_row(row + from, min(found, PF_LIST_CAP) - from);
  }
#if !PF_NEWTON
  found = pf_list_levels_below(i, xi, counts, slots, c, cell_dims, level_mask, row, found, bits);
#endif
#endif
  *bits |= st->bits;
  if (found > PF_LIST_CAP) {
    *bits |= PF_OVERFLOW_BIT;
    found = PF_LIST_CAP;
  }
  return found;
}
