/* cells.cl: the neighbour grid (after common.cl).
 *
 * Cells: a uniform grid, at most PF_CELL_CAP particles a cell, filled
 * only on the steps that rebuild the lists. Two sets of count words take
 * turns by the step's parity (cell_base: 0 or the number of cells), so an
 * insertion is one atomic_inc on a zero count: each step zeroes the cells
 * the step before filled in the other set (the first particle into a cell
 * notes it in `touched`). A cell's slots
 * are one block of PF_CELL_CAP / 8 chunks, each of 5 rows of 8 floats
 * holding copies of 8 particles' x, y, z, radius and index (as uint bits),
 * so a list build reads 8 candidates at once as float8 vectors from 160
 * contiguous bytes, without gathers.
 *
 * Neighbour lists (Verlet, with a skin): each particle keeps the indices
 * of the particles within PF_RL of it (cutoff or contact reach, plus the
 * skin) when the list was built, and where it was (XREF); with PF_NEWTON
 * (CPU devices with few cores) each pair is in only one of its two
 * particles' lists. A step that moves
 * any particle more than half the skin from XREF raises a request flag; the
 * next step then fills the cells (insert_cells, which returns at once
 * otherwise) and rebuilds every list from them (each work-item its own
 * list). Flags rotate over three words: a step reads one, raises the next,
 * clears the third. Births and removals while the lists are valid update
 * them in place (birth_linked, remove_linked); bulk additions and growth
 * force a rebuild. A step is therefore two launches on GPUs (three on CPU
 * devices), the first nearly empty. With PF_INNER (CPU devices, a cutoff:
 * dynamic pruning) the pair loop reads inner lists instead, each list's
 * entries within PF_RI (the reach plus the inner skin) when last pruned,
 * from XPRUNE; a move of half the inner skin from there raises the other
 * bit of the request word, and the next step prunes every list again
 * (pf_prune_row), as it does after a rebuild, a linked birth or a removal.
 * The lists' layout and their builds are the step form's (cpu_lists.cl,
 * gpu_lists.cl); births and removals edit them (births_removals.cl). */

#ifndef PF_LEVELS
#define PF_LEVELS 1u
#define PF_LEVEL_R0 1.0f
#define PF_CELL_CAP_UP PF_CELL_CAP
#endif

#define PF_BLOCK (5u * PF_CELL_CAP) /* floats per cell in the slots buffer (level 0) */

/* The slots open with a table, a word a cell (every level's cells, one
 * level after the other), of the float at which the cell's block starts.
 * Only the cells a sphere can reach (within about a cell of the object:
 * CellGrid::set_domain) have a block of their own; the rest have
 * PF_NO_BLOCK set and share one empty block, which insert_cells never
 * fills (most of a box around a round object is outside it: spot's is 3.8
 * times its volume). */
#define PF_NO_BLOCK 0x80000000u
uint pf_block_at(__global const float* slots, uint cell) { return as_uint(slots[cell]) & ~PF_NO_BLOCK; }
bool pf_no_block(__global const float* slots, uint cell) { return (as_uint(slots[cell]) & PF_NO_BLOCK) != 0u; }
#define PF_SLOT(s, row) (((s) >> 3) * 40u + (row) * 8u + ((s) & 7u)) /* float of slot s, row 0-4, in a block */

/* Cell coordinates of a point, clamped into the grid (a particle outside
 * keeps its neighbours: they clamp to the same or an adjacent cell). */
int4 pf_cell_of(float4 x, float4 origin, float4 inv_size, int4 dims) {
  const int4 c = convert_int4_rtn((x - origin) * inv_size);
  return clamp(c, (int4)(0), dims - (int4)(1));
}

uint pf_cell_index(int4 c, int4 dims) { return (uint)(c.x + dims.x * (c.y + dims.y * c.z)); }

/* Cell levels (PF_LEVELS > 1: unequal spheres of radii 1:2 or more;
 * EngineConstants::cell_levels). Level L holds the spheres of radius
 * above PF_LEVEL_R0 2^(L-1) up to PF_LEVEL_R0 2^L (level 0 all below, the
 * top all above) in a grid nested in level 0's: cells 2^L wide, so a
 * point's cell there is its level-0 cell >> L, and the largest pair of
 * the level reaches one cell. A sphere's partners of its level or above
 * lie in the 27 cells around it in their level; those below, in the cells
 * under the 27 of its own (pf_level_span). So a small sphere's list build
 * reads small spheres' cells, not cells sized for the largest pair. The
 * levels' cells are numbered one level after the other (their blocks
 * hold PF_CELL_CAP at level 0, PF_CELL_CAP_UP above). */
#if PF_LEVELS > 1
uint pf_level_of(float r) {
  uint level = 0u;
  while (level + 1u < PF_LEVELS && r > PF_LEVEL_R0 * (float)(1u << level)) ++level;
  return level;
}

typedef struct {
  int4 dims;   /* cells a side (w: 0) */
  uint first;  /* its first cell, over all levels */
  uint cap;    /* particles a cell */
} pf_level;

/* Level `level`'s grid, from level 0's dims. */
pf_level pf_level_at(int4 dims0, uint level) {
  pf_level g;
  g.first = 0u;
  for (uint l = 0u; l < level; ++l) {
    const int4 d = ((dims0 - (int4)(1)) >> (int4)((int)l)) + (int4)(1);
    g.first += (uint)(d.x * d.y * d.z);
  }
  g.dims = ((dims0 - (int4)(1)) >> (int4)((int)level)) + (int4)(1);
  g.dims.w = 0;
  g.cap = level == 0u ? PF_CELL_CAP : PF_CELL_CAP_UP;
  return g;
}

/* The cells [lo, hi] of level `level` (grid dims) that may hold a partner
 * of a sphere of level `own` whose cell there is c: for a level at or
 * above its own, the 27 around it (clamped); below, those under the 27. */
void pf_level_span(int4 c, uint own, uint level, int4 dims, int4* lo, int4* hi) {
  if (level >= own) {
    const int4 cl = c >> (int4)((int)(level - own));
    *lo = max(cl - (int4)(1), (int4)(0));
    *hi = min(cl + (int4)(1), dims - (int4)(1));
  } else {
    const int k = 1 << (own - level);
    *lo = max((c - (int4)(1)) * k, (int4)(0));
    *hi = min((c + (int4)(2)) * k - (int4)(1), dims - (int4)(1));
  }
}
#endif

/* The particles a list build can read from a cell (counts: this step's
 * set): its count, at most PF_CELL_CAP (a cell that overflowed sets the
 * overflow bit in *bits). */
uint pf_cell_listed(__global const uint* counts, uint cell, uint* bits) {
  const uint m = counts[cell];
  if (m > PF_CELL_CAP) *bits |= PF_OVERFLOW_BIT;
  return min(m, PF_CELL_CAP);
}

/* pf_cell_listed for a cell of `cap` slots (cell levels). */
uint pf_cell_listed_cap(__global const uint* counts, uint cell, uint cap, uint* bits) {
  const uint m = counts[cell];
  if (m > cap) *bits |= PF_OVERFLOW_BIT;
  return min(m, cap);
}

/* Whether the cell at offset (ox, oy, oz) from particle i's own cell may
 * hold a particle within PF_RL of it: `frac` is i's position within its
 * cell (0..1 a side, in cell units), cell_inv the inverse cell edge. A cell
 * whose nearest point is farther (a corner or edge cell when i sits near
 * the opposite faces) is skipped: about a quarter of the 27. */
bool pf_cell_in_reach_cells(float4 frac, int ox, int oy, int oz, float reach2);
bool pf_cell_in_reach(float4 frac, int ox, int oy, int oz, float cell_inv) {
  return pf_cell_in_reach_cells(frac, ox, oy, oz, PF_RL2 * cell_inv * cell_inv);
}

/* The same for a reach of sqrt(reach2) cells. */
bool pf_cell_in_reach_cells(float4 frac, int ox, int oy, int oz, float reach2) {
  const float gx = ox < 0 ? frac.x : ox > 0 ? 1.0f - frac.x : 0.0f;
  const float gy = oy < 0 ? frac.y : oy > 0 ? 1.0f - frac.y : 0.0f;
  const float gz = oz < 0 ? frac.z : oz > 0 ? 1.0f - frac.z : 0.0f;
  const float gap2 = fmax(gx, 0.0f) * fmax(gx, 0.0f) + fmax(gy, 0.0f) * fmax(gy, 0.0f) + fmax(gz, 0.0f) * fmax(gz, 0.0f);
  return gap2 < 1.0001f * reach2;
}

/* Lists every particle in this step's cells (count words from cell_base
 * on), on the steps whose lists are rebuilt (force, or the last step
 * raised request[request_read]). Also empties the cells the last step
 * filled in the other set: by parity, touched[k] is the cell + 1 that
 * particle k was first into (0: none) and touched_upto the particles the
 * step listed (0 when it did not rebuild). Each work-item takes a run of
 * consecutive particles (CPU devices launch a few items a core: a
 * stride of the item count sent each core's writes all over the cells,
 * and filled each cell out of index order for the list build to sort; GPU
 * forms launch an item a particle, where the two are the same). */
__kernel void insert_cells(__global const float4* X, __global uint* counts, __global float* slots, const uint cell_base,
                           const uint cells, __global uint* touched, __global uint* touched_upto,
                           const uint touched_stride, const float4 cell_origin, const float4 cell_inv,
                           const int4 cell_dims, const uint n, __global const uint* request, const uint request_read,
                           const uint force) {
  const uint i = get_global_id(0), items = get_global_size(0);
  const uint now = cell_base == 0u ? 0u : 1u, other = 1u - now, other_base = cells - cell_base;
  const uint rebuild = force || (request[request_read] & PF_REQUEST_REBUILD);
  const uint zero_upto = touched_upto[other], zero_run = (zero_upto + items - 1u) / items;
  for (uint k = i * zero_run; k < min(zero_upto, (i + 1u) * zero_run); ++k) {
    const uint cell = touched[other * touched_stride + k];
    if (cell != 0u) counts[other_base + cell - 1u] = 0u;
  }
  if (i == 0u) touched_upto[now] = rebuild ? n : 0u;
  if (!rebuild) return;
  const uint run = (n + items - 1u) / items;
  for (uint k = i * run; k < min(n, (i + 1u) * run); ++k) { /* (most steps return before this) */
    const float4 x = X[k];
#if PF_LEVELS > 1
    const uint level = pf_level_of(x.w);
    const pf_level g = pf_level_at(cell_dims, level);
    const int4 c = pf_cell_of(x, cell_origin, cell_inv, cell_dims) >> (int4)((int)level);
    const uint cell = g.first + pf_cell_index(c, g.dims), cap = g.cap;
#else
    const uint cell = pf_cell_index(pf_cell_of(x, cell_origin, cell_inv, cell_dims), cell_dims), cap = PF_CELL_CAP;
#endif
    if (pf_no_block(slots, cell)) { /* unreachable; its own list build reports it (overflow bit) */
      touched[now * touched_stride + k] = 0u;
      continue;
    }
    __global float* block = slots + pf_block_at(slots, cell);
    const uint count = atomic_inc(&counts[cell_base + cell]);
    touched[now * touched_stride + k] = count == 0u ? cell + 1u : 0u;
    if (count < cap) {
      block[PF_SLOT(count, 0u)] = x.x;
      block[PF_SLOT(count, 1u)] = x.y;
      block[PF_SLOT(count, 2u)] = x.z;
      block[PF_SLOT(count, 3u)] = x.w;
      block[PF_SLOT(count, 4u)] = as_float(k);
    }
  }
}

// Whether j belongs in i's list: within the cutoff of their pair, or
// touching (a pair of large spheres touches past the cutoff of the smallest).
inline bool pf_in_list_range(const float4 xi, const float4 xj) {
  float4 d = xi - xj;
  d.w = 0.0f;
  const float rs = xi.w + xj.w;
  return dot(d, d) < fmax(PF_RC2 * PF_PAIR_Q2(rs), rs * rs);
}

/* For tests: the indices of each particle's neighbours (pairs the step
 * considers: d^2 < max(rc^2 q2, (r_i + r_j)^2), q2 the pair's scale), at most max_out each. */
__kernel void list_neighbours(__global const float4* X, __global const uint* counts, __global const float* slots,
                              const uint cell_base, const float4 cell_origin, const float4 cell_inv, const int4 cell_dims,
                              const uint n, __global uint* out_count, __global uint* out, const uint max_out) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const float4 xi = X[i];
  const int4 c = pf_cell_of(xi, cell_origin, cell_inv, cell_dims);
  uint found = 0;
#if PF_LEVELS > 1
  const uint own = pf_level_of(xi.w);
  for (uint level = 0u; level < PF_LEVELS; ++level) {
    const pf_level g = pf_level_at(cell_dims, level);
    int4 lo, hi;
    pf_level_span(c >> (int4)((int)own), own, level, g.dims, &lo, &hi);
    for (int cz = lo.z; cz <= hi.z; ++cz)
      for (int cy = lo.y; cy <= hi.y; ++cy)
        for (int cx = lo.x; cx <= hi.x; ++cx) {
          const uint in_level = pf_cell_index((int4)(cx, cy, cz, 0), g.dims);
          const uint m = min(counts[cell_base + g.first + in_level], g.cap);
          for (uint k = 0; k < m; ++k) {
            const uint j = as_uint(slots[pf_block_at(slots, g.first + in_level) + PF_SLOT(k, 4u)]);
            if (j == i) continue;
            if (pf_in_list_range(xi, X[j])) {
              if (found < max_out) out[i * max_out + found] = j;
              ++found;
            }
          }
        }
  }
  out_count[i] = found;
  return;
#endif
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int4 cc = c + (int4)(dx, dy, dz, 0);
        if (any(cc.xyz < (int3)(0)) || any(cc.xyz >= cell_dims.xyz)) continue;
        const uint cell = pf_cell_index(cc, cell_dims);
        const uint m = min(counts[cell_base + cell], PF_CELL_CAP);
        for (uint k = 0; k < m; ++k) {
          const uint j = as_uint(slots[pf_block_at(slots, cell) + PF_SLOT(k, 4u)]);
          if (j == i) continue;
          if (pf_in_list_range(xi, X[j])) {
            if (found < max_out) out[i * max_out + found] = j;
            ++found;
          }
        }
      }
  out_count[i] = found;
}

