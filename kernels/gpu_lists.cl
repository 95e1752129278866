/* gpu_lists.cl: the GPU form's neighbour lists (after cells.cl): the
 * rows' layout and the list build.
 *
 * Each work-item takes list entries 4 at a time, one pair per work-item,
 * with the rows of 32 consecutive particles interleaved in groups of 4
 * entries: entries 4q..4q+3 of the tile's 32 rows are 512 contiguous
 * bytes, so a warp reading (or a list build writing) 4 entries a work-item
 * moves whole lines. PF_ROW(list, i) is particle i's row, PF_AT(row, k) its
 * entry k (each uses its arguments twice: no side effects in them);
 * capacities are multiples of 32 particles and of 8 entries. A row entry
 * (PF_ENTRY) is the neighbour's index itself. PF_LIST_ROW: the row
 * births and removals edit (here PF_ROW; the CPU form packs rows). */
#define PF_ROW(list, i) ((list) + (size_t)((i) / 32u) * PF_LIST_CAP * 32u + ((i) % 32u) * 4u)
#define PF_AT(row, k) ((row)[(size_t)((k) >> 2) * 128u + ((k) & 3u)])
#define PF_LIST_ROW(list, spans, i) PF_ROW(list, i)
#define PF_ENTRY(j) (j)

/* Lists the candidates of one cell (`m` of them in `block`) for particle
 * i: pf_build_list's loop body. */
void pf_list_cell(uint i, float4 xi, __global const float* block, uint m, __global uint* row, uint* found,
                  uint4* pending) {
  for (uint k = 0; k < m; ++k) {
    const float dx = xi.x - block[PF_SLOT(k, 0u)], dy = xi.y - block[PF_SLOT(k, 1u)];
    const float dz = xi.z - block[PF_SLOT(k, 2u)];
    const uint j = as_uint(block[PF_SLOT(k, 4u)]);
    if (j != i && PF_LISTED(dx * dx + dy * dy + dz * dz, xi.w + (PF_POLY ? block[PF_SLOT(k, 3u)] : 0.0f))) {
      /* gathered in 4s and stored as one vector (see PF_ROW) */
      const uint slot = *found & 3u;
      const uint4 p = *pending;
      *pending = (uint4)(slot == 0u ? j : p.x, slot == 1u ? j : p.y, slot == 2u ? j : p.z, j);
      if (slot == 3u && *found < PF_LIST_CAP) vstore4(*pending, 0, &PF_AT(row, *found - 3u));
      ++*found;
    }
  }
}

/* Rebuilds particle i's neighbour list from the cells: indices j != i
 * with |x_i - x_j|^2 < PF_RL2 (and, with unequal spheres, their own pair's reach: PF_LISTED). Returns the count (capped at PF_LIST_CAP;
 * more set the overflow bit in *bits). One candidate at a time, in the
 * order the cells hold them, which varies run to run (atomic insertions):
 * this pair loop sums forces in fixed point, where order does not matter.
 * With cell levels (cells.cl), every level's cells that may hold a partner. */
uint pf_build_list(uint i, float4 xi, __global const uint* counts, __global const float* slots,
                   int4 c, float4 frac, float cell_inv, int4 cell_dims, __global uint* row, uint* bits) {
  uint found = 0u;
  uint4 pending = (uint4)(0u);
#if PF_LEVELS > 1
  const uint own = pf_level_of(xi.w);
  {
    const pf_level g = pf_level_at(cell_dims, own);
    if (pf_no_block(slots, g.first + pf_cell_index(c >> (int4)((int)own), g.dims)))
      *bits |= PF_OVERFLOW_BIT; /* a sphere where none can be: not listed */
  }
  const float4 at = frac + convert_float4(c); /* in level-0 cells */
  for (uint level = 0u; level < PF_LEVELS; ++level) {
    const pf_level g = pf_level_at(cell_dims, level);
    int4 lo, hi;
    pf_level_span(c >> (int4)((int)own), own, level, g.dims, &lo, &hi);
    const int4 cl = c >> (int4)((int)level);
    const float4 frac_l = at * (1.0f / (float)(1u << level)) - convert_float4(cl);
    for (int cz = lo.z; cz <= hi.z; ++cz)
      for (int cy = lo.y; cy <= hi.y; ++cy)
        for (int cx = lo.x; cx <= hi.x; ++cx) {
          /* at or above its own level, a cell of the 27 whose nearest point is a cell away holds no partner */
          if (level >= own && !pf_cell_in_reach_cells(frac_l, cx - cl.x, cy - cl.y, cz - cl.z, 1.0f)) continue;
          const uint in_level = pf_cell_index((int4)(cx, cy, cz, 0), g.dims);
          const uint m = pf_cell_listed_cap(counts, g.first + in_level, g.cap, bits);
          pf_list_cell(i, xi, slots + pf_block_at(slots, g.first + in_level), m, row, &found, &pending);
        }
  }
#else
  if (pf_no_block(slots, pf_cell_index(c, cell_dims))) *bits |= PF_OVERFLOW_BIT; /* a sphere where none can be: not listed */
  const int4 lo = max(c - (int4)(1), (int4)(0)), hi = min(c + (int4)(1), cell_dims - (int4)(1));
  for (int cz = lo.z; cz <= hi.z; ++cz)
    for (int cy = lo.y; cy <= hi.y; ++cy)
      for (int cx = lo.x; cx <= hi.x; ++cx) {
        if (!pf_cell_in_reach(frac, cx - c.x, cy - c.y, cz - c.z, cell_inv)) continue;
        const uint cell = (uint)(cx + cell_dims.x * (cy + cell_dims.y * cz));
        const uint m = pf_cell_listed(counts, cell, bits);
        pf_list_cell(i, xi, slots + pf_block_at(slots, cell), m, row, &found, &pending);
      }
#endif
  for (uint q = found & ~3u; q < found && q < PF_LIST_CAP; ++q) /* the last, partial group */
    PF_AT(row, q) = q % 4u == 0u ? pending.x : q % 4u == 1u ? pending.y : pending.z;
  if (found > PF_LIST_CAP) {
    *bits |= PF_OVERFLOW_BIT;
    found = PF_LIST_CAP;
  }
  return found;
}
