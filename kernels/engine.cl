/* engine.cl: the particle update as OpenCL C 1.2 kernels. Built after
 * physics.cl (its functions) with a prelude of #defines (the constants
 * below; src/engine/engine.cpp writes them). The defaults here only let the
 * two files compile without the prelude.
 *
 * State (float4 per particle): X = (position, radius), V = (velocity at the
 * half step, 1 / mass). The update is `advance`: it reads X and V and
 * writes X' and V', on GPUs the other halves of ping-pong buffers, so no
 * work-item reads what another writes; on CPU devices, where `advance`
 * reads only its own particle, the same buffers (in place). On GPUs it computes the pair forces itself;
 * on CPU devices a launch of `pair_forces` before it does (see below). Leapfrog (velocity Verlet written
 * with half-step velocities): u(t+1/2) = u(t-1/2) + dt F(x(t), u(t-1/2))/m,
 * F the pair forces plus the contact dashpots, x(t+1) = x(t) + dt u(t+1/2),
 * then the wall.
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
 *
 * Pair forces on CPU devices (PF_GPU_FORM 0): `pair_forces`, 8 list
 * entries at a time as float8 vectors (PoCL turns them into SIMD). With
 * PF_NEWTON it computes each listed pair once and adds its force to both
 * particles (Newton's third law: half the pair work of listing pairs
 * twice): a few work-items (one per core) each take a block of particles
 * and sum into a force buffer of their own, so nothing is written by two
 * at once; `advance` adds the buffers up and zeroes them. That costs
 * `advance` a read of every buffer for every particle, so on many cores
 * (EngineParams::newton) each pair is listed twice instead and pair_forces
 * writes each particle's force once. With PF_PAIR_QUEUE (purely repulsive
 * potentials: short rows, few entries in reach) the rows are only tested
 * and the entries in reach queued, then computed 8 pairs at a time across
 * rows (pf_queue_push). On GPUs (PF_GPU_FORM 1) `advance` sums each
 * particle's forces over its full list, one pair at a time.
 *
 * Per-step scalars (kinetic energy, speeds, counts: one float8 record a
 * particle, pf_record_merge combines two) are reduced without a launch of
 * their own, in a fixed order (so the same run gives the same sums), over
 * three steps: step t makes level-1 partials (L1), step t+1 sums chunks of
 * PF_WG of them into level-2 partials (L2), and step t+2 sums those into
 * the HISTORY record of step t: kinetic energy, max speed^2, max
 * displacement^2, lists rebuilt (0/1), then as uints: colliding pairs,
 * flagged particles, cell-overflow hits, particle count. With PF_GPU_FORM
 * (GPUs): L1 holds one sum a work-group, made in local memory, and the
 * chunk and final sums are group sums too (two levels: PF_WG_ROOT items sum
 * PF_WG / PF_WG_ROOT records each, then one item sums theirs). Without it
 * (CPU devices): L1 holds a record for each octet of particles (8
 * consecutive, the first at a multiple of 8, the last maybe partial);
 * chunk c is the serial
 * sum of group c's first item, and work-item 0 sums the L2 partials: no barrier,
 * which PoCL pays for in loop overhead. finalize_history finishes the (at
 * most two) steps still in flight by the same sums.
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
#define PF_WG 64u
#define PF_WG_ROOT 8u
#define PF_GPU_FORM 0
#define PF_NEWTON 1
#define PF_PAIR_QUEUE 1
#define PF_INNER 1
#define PF_RI2 1.4f
#define PF_HALF_INNER2 0.0025f
#define PF_INNER_SKIN 0.1f
#define PF_CONTACT 1.0f
#define PF_FIX_SCALE 1.0e9f
#define PF_FIX_MAX 1.0e6f
#endif

/* EngineParams::step_form: PF_GPU_FORM 0 (CPU devices) pairs 8 list
 * entries at a time as float8 vectors, with each list row contiguous.
 * PF_GPU_FORM 1 (GPUs) takes entries 4 at a time, one pair per work-item,
 * with the rows of 32 consecutive particles interleaved in groups of 4
 * entries: entries 4q..4q+3 of the tile's 32 rows are 512 contiguous
 * bytes, so a warp reading (or a list build writing) 4 entries a work-item
 * moves whole lines. PF_ROW(list, i) is particle i's row, PF_AT(row, k) its
 * entry k (each uses its arguments twice: no side effects in them);
 * capacities are multiples of 32 particles and of 8 entries. */
#if !PF_GPU_FORM
#define PF_ROW(list, i) ((list) + (size_t)(i) * PF_LIST_CAP)
#define PF_AT(row, k) ((row)[k])
#else
#define PF_ROW(list, i) ((list) + (size_t)((i) / 32u) * PF_LIST_CAP * 32u + ((i) % 32u) * 4u)
#define PF_AT(row, k) ((row)[(size_t)((k) >> 2) * 128u + ((k) & 3u)])
#endif

/* CPU devices with PF_NEWTON pack each block's rows one after the other
 * at a rebuild, each with PF_ROW_SLACK entries of room for linked births
 * after it (pair_forces): spans[i] = (the row's first word, its room, at
 * most PF_LIST_CAP), and PF_LIST_ROW is the row; elsewhere PF_ROW. A
 * block's rows fit in its PF_ROW_STRIDE words a particle. */
#define PF_ROW_SLACK 8u
#define PF_ROW_STRIDE (PF_LIST_CAP + PF_ROW_SLACK)
#if !PF_GPU_FORM && PF_NEWTON
#define PF_LIST_ROW(list, spans, i) ((list) + (spans)[i].x)
#else
#define PF_LIST_ROW(list, spans, i) PF_ROW(list, i)
#endif

/* A row entry names neighbour j: on GPUs j itself; on CPU devices the byte
 * offset of its float4 (16 j, so at most 2^27 particles: the AVX-512
 * gathers read the offsets as signed), which the pair
 * loop adds to X, V or F as it is (x86 scales an index by at most 8: a
 * plain index costs a shift a lane). PF_LOAD_AT / PF_REF_AT: the float4
 * of an entry, read-only or to update. */
#if !PF_GPU_FORM
#define PF_ENTRY(j) ((j) << 4)
#define PF_LOAD_AT(base, e) (*(__global const float4*)((__global const uchar*)(base) + (e)))
#define PF_REF_AT(base, e) (*(__global float4*)((__global uchar*)(base) + (e)))
#else
#define PF_ENTRY(j) (j)
#endif

#define PF_BLOCK (5u * PF_CELL_CAP) /* floats per cell in the slots buffer */
#define PF_SLOT(s, row) (((s) >> 3) * 40u + (row) * 8u + ((s) & 7u)) /* float of slot s, row 0-4, in a block */
/* Bits a step sets for a particle (pf_build_list, the wall). */
#define PF_FLAGGED_BIT 0x1u
#define PF_OVERFLOW_BIT 0x2u
/* Bits of a request word (request[]): rebuild the lists, prune the inner lists. */
#define PF_REQUEST_REBUILD 0x1u
#define PF_REQUEST_PRUNE 0x2u

/* Cell coordinates of a point, clamped into the grid (a particle outside
 * keeps its neighbours: they clamp to the same or an adjacent cell). */
int4 pf_cell_of(float4 x, float4 origin, float4 inv_size, int4 dims) {
  const int4 c = convert_int4_rtn((x - origin) * inv_size);
  return clamp(c, (int4)(0), dims - (int4)(1));
}

uint pf_cell_index(int4 c, int4 dims) { return (uint)(c.x + dims.x * (c.y + dims.y * c.z)); }

/* The particles a list build can read from a cell (counts: this step's
 * set): its count, at most PF_CELL_CAP (a cell that overflowed sets the
 * overflow bit in *bits). */
uint pf_cell_listed(__global const uint* counts, uint cell, uint* bits) {
  const uint m = counts[cell];
  if (m > PF_CELL_CAP) *bits |= PF_OVERFLOW_BIT;
  return min(m, PF_CELL_CAP);
}

/* A particle's record: (kinetic energy, speed^2, displacement^2, lists
 * rebuilt, then as uints: colliding pairs, flagged, cell overflow, count).
 * Squares: their maxima are the squares of the maxima, so the host takes
 * the one square root of each, not every particle. */
float8 pf_record(float ke, float speed2, float disp2, uint rebuilt, uint pairs, uint flagged, uint overflow, uint n) {
  return (float8)(ke, speed2, disp2, (float)rebuilt, as_float4((uint4)(pairs, flagged, overflow, n)));
}

/* Two records as one: sums, maxima, counts summed, the particle count the larger. */
float8 pf_record_merge(float8 a, float8 b) {
  const uint4 ua = as_uint4(a.s4567), ub = as_uint4(b.s4567);
  return (float8)(a.s0 + b.s0, fmax(a.s1, b.s1), fmax(a.s2, b.s2), fmax(a.s3, b.s3),
                  as_float4((uint4)(ua.x + ub.x, ua.y + ub.y, ua.z + ub.z, max(ua.w, ub.w))));
}

/* Partial `first + lid` of `count` (zero past the end). */
float8 pf_partial_at(__global const float8* src, uint count, uint first, uint lid) {
  return first + lid < count ? src[first + lid] : (float8)(0.0f);
}

/* Item lid's share of all `count` partials: lid, lid + PF_WG, ... in order. */
float8 pf_partials_strided(__global const float8* src, uint count, uint lid) {
  float8 s = (float8)(0.0f);
  for (uint k = lid; k < count; k += PF_WG) s = pf_record_merge(s, src[k]);
  return s;
}

/* pf_record_merge for a running sum a that starts from an empty record
 * (the CPU form's serial sums): the maxima by compares, not fmax, whose
 * NaN handling PoCL spends instructions on. A NaN in b loses, as with
 * fmax, and a, built from such merges, holds none. */
float8 pf_partial_add(float8 a, float8 b) {
  const uint4 ua = as_uint4(a.s4567), ub = as_uint4(b.s4567);
  return (float8)(a.s0 + b.s0, b.s1 > a.s1 ? b.s1 : a.s1, b.s2 > a.s2 ? b.s2 : a.s2, b.s3 > a.s3 ? b.s3 : a.s3,
                  as_float4((uint4)(ua.x + ub.x, ua.y + ub.y, ua.z + ub.z, max(ua.w, ub.w))));
}

/* Partials [first, end) of src summed by one work-item in a fixed order
 * (the CPU form's chunk and final sums): four interleaved runs (k mod 4
 * from `first`, the tail in the first), added up at the end, so that the
 * kinetic energy's chain of additions is a quarter as long (-5% of
 * `advance` at N = 1e5). */
float8 pf_partials_serial(__global const float8* src, uint first, uint end) {
  float8 a0 = (float8)(0.0f), a1 = a0, a2 = a0, a3 = a0;
  uint k = first;
  for (; k + 4u <= end; k += 4u) {
    a0 = pf_partial_add(a0, src[k]);
    a1 = pf_partial_add(a1, src[k + 1u]);
    a2 = pf_partial_add(a2, src[k + 2u]);
    a3 = pf_partial_add(a3, src[k + 3u]);
  }
  for (; k < end; ++k) a0 = pf_partial_add(a0, src[k]);
  return pf_partial_add(pf_partial_add(a0, a1), pf_partial_add(a2, a3));
}

/* Up to three group sums at once (one record a work-item in each of
 * part[0..2], stored by the caller before a barrier): item w < 3 returns
 * sum w, in a fixed order, where bit w of `need` (the same in the whole
 * group) is set. Every item of the group must call it. */
float8 pf_group_sums(__local float8* part, __local float8* mid, uint lid, uint need) {
  const uint per = PF_WG / PF_WG_ROOT;
  if (lid < 3u * PF_WG_ROOT && ((need >> (lid / PF_WG_ROOT)) & 1u)) {
    __local const float8* run = part + (lid / PF_WG_ROOT) * PF_WG + (lid % PF_WG_ROOT) * per;
    float8 s = run[0];
    for (uint k = 1; k < per; ++k) s = pf_record_merge(s, run[k]);
    mid[lid] = s;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  float8 total = (float8)(0.0f);
  if (lid < 3u && ((need >> lid) & 1u)) {
    __local const float8* run = mid + lid * PF_WG_ROOT;
    total = run[0];
    for (uint k = 1; k < PF_WG_ROOT; ++k) total = pf_record_merge(total, run[k]);
  }
  return total;
}

/* Clang's x86 builtins, where the kernel compiler targets x86 (PoCL on a
 * CPU defines the target's feature macros): PF_X86_AVX512 with AVX-512VL,
 * PF_X86_AVX with AVX. Everything that uses them has a plain OpenCL C
 * fallback, which oclgrind runs in ctest. */
#if defined(__clang__) && defined(__x86_64__) && defined(__AVX512VL__)
#define PF_X86_AVX512 1
#elif defined(__clang__) && defined(__x86_64__) && defined(__AVX__)
#define PF_X86_AVX 1
#endif

/* With AVX-512VL, an 8-lane mask's sign bits as the bits of a mask
 * register (PF_MASK8), which one instruction tests or counts. */
#if defined(PF_X86_AVX512)
#define PF_MASK8(m) __builtin_ia32_cvtd2mask256(m)
/* The lanes of v where `mask` (a PF_MASK8) is set, packed to the front;
 * the lanes after them are fill's. */
#define PF_PACK8F(v, fill, mask) __builtin_ia32_compresssf256_mask((v), (fill), (mask))
#define PF_PACK8U(v, fill, mask) as_uint8(__builtin_ia32_compresssi256_mask(as_int8(v), as_int8(fill), (mask)))
#endif

/* any() of an 8-lane mask: a mask-register test with AVX-512VL; elsewhere
 * two ORs and one test (PoCL makes four branches of any()). */
bool pf_any8(int8 m) {
#if defined(PF_MASK8)
  return PF_MASK8(m) != 0;
#else
  const int4 a = m.lo | m.hi;
  const int2 b = a.lo | a.hi;
  return (b.x | b.y) < 0;
#endif
}

/* The set lanes of an 8-lane mask: a popcount of the mask register with
 * AVX-512VL; elsewhere summed as floats (oclgrind 1.x mis-sums the lanes
 * of integer masks). */
uint pf_count8(int8 m) {
#if defined(PF_MASK8)
  return popcount((uint)PF_MASK8(m));
#else
  const float8 hit = select((float8)(0.0f), (float8)(1.0f), m);
  return (uint)(hit.s0 + hit.s1 + hit.s2 + hit.s3 + hit.s4 + hit.s5 + hit.s6 + hit.s7);
#endif
}

/* 1 / sqrt(x) for 8 lanes without the divider: the CPU's reciprocal
 * square-root estimate (AVX-512VL: 14 bits; AVX: 12 bits) and one Newton
 * step, within about 2 ulp of the rounded result; rsqrt() elsewhere. PoCL
 * compiles rsqrt() and native_rsqrt() to a square root and a division, the
 * two slowest instructions of the pair loop (one unit, not pipelined). */
float8 pf_rsqrt8(float8 x) {
#if defined(PF_X86_AVX512)
  const float8 y = __builtin_ia32_rsqrt14ps256_mask(x, (float8)(0.0f), (uchar)0xff);
#elif defined(PF_X86_AVX)
  const float8 y = __builtin_ia32_rsqrtps256(x);
#else
  return rsqrt(x);
#endif
#if defined(PF_X86_AVX512) || defined(PF_X86_AVX)
  return y * (1.5f - 0.5f * x * y * y);
#endif
}

#if !PF_GPU_FORM
/* Eight float4s p[0..7] as four lane vectors (their x, y, z and w): a 4x4
 * transpose in each 128-bit half (element by element, PoCL spends a
 * broadcast and a blend on each of the 32 lanes). */
void pf_transpose8(const float4* p, float8* x, float8* y, float8* z, float8* w) {
  const float8 a = (float8)(p[0], p[4]), b = (float8)(p[1], p[5]), c = (float8)(p[2], p[6]), d = (float8)(p[3], p[7]);
  const float8 ab_lo = (float8)(a.s0, b.s0, a.s1, b.s1, a.s4, b.s4, a.s5, b.s5);
  const float8 ab_hi = (float8)(a.s2, b.s2, a.s3, b.s3, a.s6, b.s6, a.s7, b.s7);
  const float8 cd_lo = (float8)(c.s0, d.s0, c.s1, d.s1, c.s4, d.s4, c.s5, d.s5);
  const float8 cd_hi = (float8)(c.s2, d.s2, c.s3, d.s3, c.s6, d.s6, c.s7, d.s7);
  *x = (float8)(ab_lo.s01, cd_lo.s01, ab_lo.s45, cd_lo.s45);
  *y = (float8)(ab_lo.s23, cd_lo.s23, ab_lo.s67, cd_lo.s67);
  *z = (float8)(ab_hi.s01, cd_hi.s01, ab_hi.s45, cd_hi.s45);
  *w = (float8)(ab_hi.s23, cd_hi.s23, ab_hi.s67, cd_hi.s67);
}

/* pf_transpose8 backwards: lane l of (gx, gy, gz, gw) as p[l]. */
void pf_untranspose8(float8 gx, float8 gy, float8 gz, float8 gw, float4* p) {
  const float8 xy_lo = (float8)(gx.s0, gy.s0, gx.s1, gy.s1, gx.s4, gy.s4, gx.s5, gy.s5);
  const float8 xy_hi = (float8)(gx.s2, gy.s2, gx.s3, gy.s3, gx.s6, gy.s6, gx.s7, gy.s7);
  const float8 zw_lo = (float8)(gz.s0, gw.s0, gz.s1, gw.s1, gz.s4, gw.s4, gz.s5, gw.s5);
  const float8 zw_hi = (float8)(gz.s2, gw.s2, gz.s3, gw.s3, gz.s6, gw.s6, gz.s7, gw.s7);
  p[0] = (float4)(xy_lo.s01, zw_lo.s01);
  p[1] = (float4)(xy_lo.s23, zw_lo.s23);
  p[2] = (float4)(xy_hi.s01, zw_hi.s01);
  p[3] = (float4)(xy_hi.s23, zw_hi.s23);
  p[4] = (float4)(xy_lo.s45, zw_lo.s45);
  p[5] = (float4)(xy_lo.s67, zw_lo.s67);
  p[6] = (float4)(xy_hi.s45, zw_hi.s45);
  p[7] = (float4)(xy_hi.s67, zw_hi.s67);
}

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
 * latency (+6% at rc 2.5, bench_variants). The pair queue's short rows do
 * not, so it keeps pf_gather8 (-12% with gathers there). w: 0 where the
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
#endif

/* pf_lj_force_scale of physics.cl for 8 pairs at once, given 1/d^2 and
 * 1/d, with the prelude's constants (the same formula with the divisions
 * shared; the oracle tests tie the two). */
float8 pf_lj_force_scale8(float8 inv_d2, float8 inv_d) {
  const float8 x = PF_SIGMA2 * inv_d2;
#if PF_EXP_B_HALF > 0
  float8 sb = x;
#pragma unroll
  for (int k = 1; k < PF_EXP_B_HALF; ++k) sb *= x;
#else
  const float8 sb = pow(x, (float8)(0.5f * PF_EXP_B));
#endif
#if PF_EXP_B_HALF > 0 && PF_EXP_A_HALF == 2 * PF_EXP_B_HALF
  /* a = 2b (12-6): 4 eps (a sb - b) sb / d^2, two multiplies fewer on the
   * dependency chain from d^2 to the force than the general form */
  const float8 k = (4.0f * PF_EPS * PF_EXP_A * sb - 4.0f * PF_EPS * PF_EXP_B) * (sb * inv_d2);
#else
#if PF_EXP_A_HALF > 0
  float8 sa = x;
#pragma unroll
  for (int k = 1; k < PF_EXP_A_HALF; ++k) sa *= x;
#else
  const float8 sa = pow(x, (float8)(0.5f * PF_EXP_A));
#endif
  const float8 k = 4.0f * PF_EPS * (PF_EXP_A * sa - PF_EXP_B * sb) * inv_d2;
#endif
  const float8 k_max = PF_FORCE_CAP * inv_d;
  /* compares, not fmin / fmax: k is never NaN, and PoCL's fmin handles NaNs */
  return select(select(k, k_max, k > k_max), -k_max, k < -k_max);
}

/* Lists every particle in this step's cells (count words from cell_base
 * on), on the steps whose lists are rebuilt (force, or the last step
 * raised request[request_read]). Also empties the cells the last step
 * filled in the other set: by parity, touched[k] is the cell + 1 that
 * particle k was first into (0: none) and touched_upto the particles the
 * step listed (0 when it did not rebuild). */
__kernel void insert_cells(__global const float4* X, __global uint* counts, __global float* slots, const uint cell_base,
                           const uint cells, __global uint* touched, __global uint* touched_upto,
                           const uint touched_stride, const float4 cell_origin, const float4 cell_inv,
                           const int4 cell_dims, const uint n, __global const uint* request, const uint request_read,
                           const uint force) {
  const uint i = get_global_id(0), items = get_global_size(0);
  const uint now = cell_base == 0u ? 0u : 1u, other = 1u - now, other_base = cells - cell_base;
  const uint rebuild = force || (request[request_read] & PF_REQUEST_REBUILD);
  for (uint k = i; k < touched_upto[other]; k += items) {
    const uint cell = touched[other * touched_stride + k];
    if (cell != 0u) counts[other_base + cell - 1u] = 0u;
  }
  if (i == 0u) touched_upto[now] = rebuild ? n : 0u;
  if (!rebuild) return;
  for (uint k = i; k < n; k += items) { /* CPU devices launch a few items a core: most steps return at once */
    const float4 x = X[k];
    const uint cell = pf_cell_index(pf_cell_of(x, cell_origin, cell_inv, cell_dims), cell_dims);
    const uint count = atomic_inc(&counts[cell_base + cell]);
    touched[now * touched_stride + k] = count == 0u ? cell + 1u : 0u;
    if (count < PF_CELL_CAP) {
      __global float* block = slots + cell * PF_BLOCK;
      block[PF_SLOT(count, 0u)] = x.x;
      block[PF_SLOT(count, 1u)] = x.y;
      block[PF_SLOT(count, 2u)] = x.z;
      block[PF_SLOT(count, 3u)] = x.w;
      block[PF_SLOT(count, 4u)] = as_float(k);
    }
  }
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
 * out. On GPUs it also takes a slot in b's list (list_count[b] is 0
 * beforehand); on CPU devices, where each pair is in one list, b's list
 * stays empty. Item n writes the newcomer (and, with PF_INNER, asks the
 * next step to prune). A full list raises the rebuild request the next
 * step reads. */
__kernel void birth_linked(__global float4* X, __global float4* V, __global uint* flags, __global float* C,
                           __global uint* list, __global uint* list_count, __global uint2* spans, __global float4* XREF,
                           __global uint* request, const uint request_next, const uint n, const float4 x,
                           const float4 v) {
  const uint i = get_global_id(0);
  if (i == n) {
    X[n] = x;
    V[n] = v;
    flags[n] = 0u;
    C[n] = 0.0f;
    XREF[n] = x;
#if !PF_GPU_FORM && PF_NEWTON
    spans[n] = (uint2)(0u, 0u); /* its list stays empty */
#endif
    /* the inner lists are packed by pair_forces' blocks, which the count sets */
    if (PF_INNER) atomic_or(&request[request_next], PF_REQUEST_PRUNE);
    return;
  }
  if (i > n) return;
  float4 d = XREF[i] - x;
  d.w = 0.0f;
  if (dot(d, d) >= PF_RL2) return;
  const uint mine = list_count[i];
#if !PF_GPU_FORM && PF_NEWTON
  /* each pair in one list: the newcomer's stays empty */
  if (mine < spans[i].y) {
    PF_AT(PF_LIST_ROW(list, spans, i), mine) = PF_ENTRY(n);
    list_count[i] = mine + 1u;
  } else {
    atomic_or(&request[request_next], PF_REQUEST_REBUILD);
  }
  return;
#endif
  const uint slot = atomic_inc(&list_count[n]);
  if (mine < PF_LIST_CAP && slot < PF_LIST_CAP) {
    PF_AT(PF_ROW(list, i), mine) = PF_ENTRY(n);
    list_count[i] = mine + 1u;
    PF_AT(PF_ROW(list, n), slot) = PF_ENTRY(i);
  } else {
    atomic_or(&request[request_next], PF_REQUEST_REBUILD);
  }
}

/* One removal while the lists are valid (one launch over n items, n the
 * count before it): particle `last` = n - 1 takes the place of `gone`. Item
 * `gone` copies the last particle's state and list (without `gone`); every
 * other item but `last` drops `gone` from its own list and renames `last`
 * to `gone`. The host then zeroes list_count[last]. */
__kernel void remove_linked(__global float4* X, __global float4* V, __global uint* flags, __global float* C,
                            __global uint* list, __global uint* list_count, __global uint2* spans,
                            __global float4* XREF, const uint n, const uint gone, __global uint* request,
                            const uint request_next) {
  const uint i = get_global_id(0);
  const uint last = n - 1u;
  if (PF_INNER && i == 0u) atomic_or(&request[request_next], PF_REQUEST_PRUNE); /* the inner lists name them too */
  if (i >= last) return;
  if (i == gone) {
    X[i] = X[last];
    V[i] = V[last];
    flags[i] = flags[last];
    C[i] = C[last];
    XREF[i] = XREF[last];
#if !PF_GPU_FORM && PF_NEWTON
    spans[i] = spans[last]; /* packed rows: the last particle's row becomes this one's, filtered in place */
#endif
    __global uint* row = PF_LIST_ROW(list, spans, i);
    __global const uint* from = PF_LIST_ROW(list, spans, last);
    const uint count = min(list_count[last], PF_LIST_CAP);
    uint kept = 0u;
    for (uint k = 0; k < count; ++k)
      if (PF_AT(from, k) != PF_ENTRY(gone)) {
        PF_AT(row, kept) = PF_AT(from, k); /* (PF_AT uses its arguments twice: no ++ in them) */
        ++kept;
      }
    list_count[i] = kept;
    return;
  }
  __global uint* row = PF_LIST_ROW(list, spans, i);
  uint count = min(list_count[i], PF_LIST_CAP);
  for (uint k = 0; k < count;) {
    if (PF_AT(row, k) == PF_ENTRY(gone)) {
      --count;
      PF_AT(row, k) = PF_AT(row, count);
    } else {
      if (PF_AT(row, k) == PF_ENTRY(last)) PF_AT(row, k) = PF_ENTRY(gone);
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

/* Finishes the steps in flight (one work-group), by the same sums the
 * steps would have done: the last step's level-1 partials (L1_last, g1 of
 * them; 0: none) into level 2 (L2_scratch), then into its history record;
 * and the step before's level-2 partials (L2_prev, g2_prev; 0: none) into
 * its record. */
__kernel __attribute__((reqd_work_group_size(PF_WG, 1, 1))) void finalize_history(
    __global const float8* L1_last, const uint g1, __global float8* L2_scratch, __global const float8* L2_prev,
    const uint g2_prev, __global float8* history, const uint slot_last, const uint slot_prev) {
  const uint lid = get_local_id(0);
  const uint g2 = (g1 + PF_WG - 1u) / PF_WG;
#if PF_GPU_FORM
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
#else
  if (lid != 0u) return;
  for (uint c = 0; c < g2; ++c) L2_scratch[c] = pf_partials_serial(L1_last, c * PF_WG, min(g1, (c + 1u) * PF_WG));
  if (g2 > 0u) history[slot_last] = pf_partials_serial(L2_scratch, 0u, g2);
  if (g2_prev > 0u) history[slot_prev] = pf_partials_serial(L2_prev, 0u, g2_prev);
#endif
}

/* For tests: the indices of each particle's neighbours (pairs the step
 * considers: d^2 < max(rc^2, (r_i + r_j)^2)), at most max_out each. */
__kernel void list_neighbours(__global const float4* X, __global const uint* counts, __global const float* slots,
                              const uint cell_base, const float4 cell_origin, const float4 cell_inv, const int4 cell_dims,
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
        const uint m = min(counts[cell_base + cell], PF_CELL_CAP);
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

#if !PF_GPU_FORM
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
 * no longer goes one way or the other by chance (-8% a step at rc 2.5). */
uint pf_prune_row(uint i, float4 xi, __global const uint* row, uint count, __global const float4* X,
                  __global uint* inner, uint* touching) {
  uint near_count = 0u, apart_count = 0u;
  uint apart[PF_LIST_CAP + 8u];
  for (uint k = 0; k < count; k += 8u) {
    float8 dx, dy, dz, rs;
    pf_gather8(X, row + k, &dx, &dy, &dz, &rs); /* (1-2% faster here than the hardware gathers) */
    dx = xi.x - dx;
    dy = xi.y - dy;
    dz = xi.z - dz;
    const float8 d2 = dx * dx + dy * dy + dz * dz;
    const int8 lane = (int8)(0, 1, 2, 3, 4, 5, 6, 7) + (int8)((int)k);
    const int8 within = (lane < (int8)((int)count)) & (d2 < PF_RI2);
    /* (1 + 1e-5: the rounding of the square, on the safe side) */
    const float8 reach = fmax(rs + xi.w, PF_CONTACT) + PF_INNER_SKIN;
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
#endif

/* Whether the cell at offset (ox, oy, oz) from particle i's own cell may
 * hold a particle within PF_RL of it: `frac` is i's position within its
 * cell (0..1 a side, in cell units), cell_inv the inverse cell edge. A cell
 * whose nearest point is farther (a corner or edge cell when i sits near
 * the opposite faces) is skipped: about a quarter of the 27. */
bool pf_cell_in_reach(float4 frac, int ox, int oy, int oz, float cell_inv) {
  const float gx = ox < 0 ? frac.x : ox > 0 ? 1.0f - frac.x : 0.0f;
  const float gy = oy < 0 ? frac.y : oy > 0 ? 1.0f - frac.y : 0.0f;
  const float gz = oz < 0 ? frac.z : oz > 0 ? 1.0f - frac.z : 0.0f;
  const float gap2 = fmax(gx, 0.0f) * fmax(gx, 0.0f) + fmax(gy, 0.0f) * fmax(gy, 0.0f) + fmax(gz, 0.0f) * fmax(gz, 0.0f);
  return gap2 < 1.0001f * PF_RL2 * cell_inv * cell_inv;
}

#if PF_GPU_FORM
/* Rebuilds particle i's neighbour list from the cells: indices j != i
 * with |x_i - x_j|^2 < PF_RL2. Returns the count (capped at PF_LIST_CAP;
 * more set the overflow bit in *bits). One candidate at a time, in the
 * order the cells hold them, which varies run to run (atomic insertions):
 * this pair loop sums forces in fixed point, where order does not matter. */
uint pf_build_list(uint i, float4 xi, __global const uint* counts, __global const float* slots,
                   int4 c, float4 frac, float cell_inv, int4 cell_dims, __global uint* row, uint* bits) {
  uint found = 0u;
  uint4 pending = (uint4)(0u);
  const int4 lo = max(c - (int4)(1), (int4)(0)), hi = min(c + (int4)(1), cell_dims - (int4)(1));
  for (int cz = lo.z; cz <= hi.z; ++cz)
    for (int cy = lo.y; cy <= hi.y; ++cy)
      for (int cx = lo.x; cx <= hi.x; ++cx) {
        if (!pf_cell_in_reach(frac, cx - c.x, cy - c.y, cz - c.z, cell_inv)) continue;
        const uint cell = (uint)(cx + cell_dims.x * (cy + cell_dims.y * cz));
        const uint m = pf_cell_listed(counts, cell, bits);
        __global const float* block = slots + cell * PF_BLOCK;
        for (uint k = 0; k < m; ++k) {
          const float dx = xi.x - block[PF_SLOT(k, 0u)], dy = xi.y - block[PF_SLOT(k, 1u)];
          const float dz = xi.z - block[PF_SLOT(k, 2u)];
          const uint j = as_uint(block[PF_SLOT(k, 4u)]);
          if (j != i && dx * dx + dy * dy + dz * dz < PF_RL2) {
            /* gathered in 4s and stored as one vector (see PF_ROW) */
            const uint slot = found & 3u;
            pending = (uint4)(slot == 0u ? j : pending.x, slot == 1u ? j : pending.y, slot == 2u ? j : pending.z, j);
            if (slot == 3u && found < PF_LIST_CAP) vstore4(pending, 0, &PF_AT(row, found - 3u));
            ++found;
          }
        }
      }
  for (uint q = found & ~3u; q < found && q < PF_LIST_CAP; ++q) /* the last, partial group */
    PF_AT(row, q) = q % 4u == 0u ? pending.x : q % 4u == 1u ? pending.y : pending.z;
  if (found > PF_LIST_CAP) {
    *bits |= PF_OVERFLOW_BIT;
    found = PF_LIST_CAP;
  }
  return found;
}
#else
/* The candidates of the CPU form's list builds for the particles of one
 * cell: the particles of the cells of its stencil, copied once for the run
 * of consecutive particles in that cell (as the particles lie after
 * Engine::sort_by_cells) into contiguous arrays, so that each particle's
 * build is one pass of 8-lane loads over them. With PF_NEWTON the stencil
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
#define PF_STENCIL_CAP (PF_STENCIL_CELLS * PF_CELL_CAP + 8u) /* 8 lanes of slack past the last */
typedef struct {
  float x[PF_STENCIL_CAP], y[PF_STENCIL_CAP], z[PF_STENCIL_CAP];
  uint e[PF_STENCIL_CAP]; /* as row entries (PF_ENTRY) */
  uint count, own;        /* candidates; the cell's own ones ([0, own)) */
  uint cell;              /* whose stencil (UINT_MAX: none yet) */
  uint bits;              /* the overflow bit, where a cell of the stencil overflowed */
} pf_stencil;

/* Copies cell `cell`'s listed particles to the end of st's candidates, in index order. */
void pf_stencil_add(pf_stencil* st, __global const uint* counts, __global const float* slots, uint cell) {
  const uint m = pf_cell_listed(counts, cell, &st->bits), at = st->count;
  __global const float* block = slots + cell * PF_BLOCK;
  for (uint k = 0; k < m; k += 8u) { /* whole chunks; the lanes past m are overwritten or never read */
    __global const float* chunk = block + 5u * k;
    vstore8(vload8(0, chunk), 0, st->x + at + k);
    vstore8(vload8(1, chunk), 0, st->y + at + k);
    vstore8(vload8(2, chunk), 0, st->z + at + k);
    vstore8(as_uint8(vload8(4, chunk)) << 4u, 0, st->e + at + k);
  }
  for (uint k = at + 1u; k < at + m; ++k) { /* insertion sort: the cells are nearly in order */
    const uint e = st->e[k];
    const float x = st->x[k], y = st->y[k], z = st->z[k];
    uint q = k;
    for (; q > at && st->e[q - 1u] > e; --q) {
      st->e[q] = st->e[q - 1u];
      st->x[q] = st->x[q - 1u];
      st->y[q] = st->y[q - 1u];
      st->z[q] = st->z[q - 1u];
    }
    st->e[q] = e;
    st->x[q] = x;
    st->y[q] = y;
    st->z[q] = z;
  }
  st->count = at + m;
}

/* st becomes the stencil of the cell at coordinates c. */
void pf_stencil_gather(pf_stencil* st, __global const uint* counts, __global const float* slots, int4 c,
                       int4 cell_dims) {
  st->count = 0u;
  st->bits = 0u;
  st->cell = pf_cell_index(c, cell_dims);
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

/* Rebuilds particle i's neighbour list from its cell's stencil: the
 * candidates j != i with |x_i - x_j|^2 < PF_RL2 (with PF_NEWTON, of the
 * cell's own particles only those with j > i), in the stencil's order.
 * Returns the count (capped at PF_LIST_CAP; more set the overflow bit in
 * *bits, as does a stencil cell that overflowed). */
uint pf_build_list(uint i, float4 xi, const pf_stencil* st, __global uint* row, uint* bits) {
  uint found = 0u;
  const uint8 ei = (uint8)(PF_ENTRY(i));
  for (uint k = 0; k < st->count; k += 8u) {
    const float8 dx = xi.x - vload8(0, st->x + k), dy = xi.y - vload8(0, st->y + k), dz = xi.z - vload8(0, st->z + k);
    const uint8 e = vload8(0, st->e + k);
    const uint8 lane = (uint8)(0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u) + (uint8)(k);
#if PF_NEWTON
    const int8 partner = lane >= (uint8)(st->own) | e > ei;
#else
    const int8 partner = e != ei;
#endif
    const int8 near = (lane < (uint8)(st->count)) & partner & (dx * dx + dy * dy + dz * dz < PF_RL2);
    /* no branch on whether any lane hit: at rc = 2.5 sigma about half the
     * chunks do, at random, and the mispredictions cost more than a store */
    pf_store_hits8(row, found, e, near, PF_ENTRY(i));
    found += pf_count8(near);
  }
  *bits |= st->bits;
  if (found > PF_LIST_CAP) {
    *bits |= PF_OVERFLOW_BIT;
    found = PF_LIST_CAP;
  }
  return found;
}
#endif

#if !PF_GPU_FORM
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
 * the cutoff and where not `near`; d2 finite in every lane). Pairs on top
 * of each other get a fixed, antisymmetric direction (its sign from
 * jj > i_entry), written back to d and d2. *inv_d: 1/|d|. Shared by the
 * row loop and the pair queue, so both compute the same forces. */
float8 pf_potential8(float8* dx, float8* dy, float8* dz, float8* d2, int8 near, uint8 i_entry, uint8 jj,
                     float8* inv_d) {
  const int8 tiny = near & (*d2 < PF_D_MIN * PF_D_MIN);
  if (pf_any8(tiny)) {
    *dx = select(*dx, select((float8)(PF_D_MIN), (float8)(-PF_D_MIN), jj > i_entry), tiny);
    *dy = select(*dy, (float8)(0.0f), tiny);
    *dz = select(*dz, (float8)(0.0f), tiny);
    *d2 = select(*d2, (float8)(PF_D_MIN * PF_D_MIN), tiny);
  }
  /* 1/d^2 by a division, beside (not after) the square root: a shorter chain */
  *inv_d = pf_rsqrt8(*d2);
  const float8 inv_d2 = 1.0f / *d2;
  return select((float8)(0.0f), pf_lj_force_scale8(inv_d2, *inv_d), near & (*d2 < PF_RC2));
}

/* The dashpots of the `contact` lanes (physics.cl pf_contact_damping, 8
 * lanes) added to g, from d, 1/|d| and both sides' velocities and inverse
 * masses. */
void pf_dashpots8(float8 dx, float8 dy, float8 dz, float8 inv_d, float8 uix, float8 uiy, float8 uiz, float8 imi,
                  float8 ujx, float8 ujy, float8 ujz, float8 imj, int8 contact, float8* gx, float8* gy, float8* gz) {
  const float8 nx = dx * inv_d, ny = dy * inv_d, nz = dz * inv_d;
  const float8 un = (uix - ujx) * nx + (uiy - ujy) * ny + (uiz - ujz) * nz;
  const float8 cf = select((float8)(0.0f), -PF_DASHPOT * pf_rsqrt8(imi + imj) * un, contact);
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
 * spilled its constants and cost 4% more. */
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
    pf_row_gather8(X, row + k, &dx, &dy, &dz, may_touch ? &rs : 0);
    dx = xi.x - dx;
    dy = xi.y - dy;
    dz = xi.z - dz;
    rs += ri;
    float8 d2 = dx * dx + dy * dy + dz * dz;
    const float8 touch2 = fmax(rs * rs, PF_CONTACT2);
    const int8 near = valid & (d2 < (may_touch ? fmax(touch2, PF_RC2) : (float8)(PF_RC2)));
    d2 = select((float8)(1.0f), d2, near); /* masked lanes stay finite */
    float8 inv_d;
    const float8 kf = pf_potential8(&dx, &dy, &dz, &d2, near, (uint8)(PF_ENTRY(i)), jj, &inv_d);
    float8 gx = kf * dx, gy = kf * dy, gz = kf * dz;
    const int8 contact = near & (d2 < touch2);
    if (may_touch && pf_any8(contact)) {
      float8 vx, vy, vz, imj;
      pf_row_gather8(V, row + k, &vx, &vy, &vz, &imj);
      pf_dashpots8(dx, dy, dz, inv_d, vi.x, vi.y, vi.z, inv_mi, vx, vy, vz, imj, contact, &gx, &gy, &gz);
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
  const float8 touch2 = fmax(rs * rs, PF_CONTACT2);
  float8 d2 = select((float8)(1.0f), dx * dx + dy * dy + dz * dz, ok); /* unused lanes stay finite */
  float8 inv_d;
  const float8 kf = pf_potential8(&dx, &dy, &dz, &d2, ok, ii, jj, &inv_d);
  float8 gx = kf * dx, gy = kf * dy, gz = kf * dz, gw = (float8)(0.0f);
  const int8 contact = ok & (d2 < touch2);
  if (pf_any8(contact)) {
    float8 vix, viy, viz, imi, vjx, vjy, vjz, imj;
    pf_gather8_private(V, q->i, &vix, &viy, &viz, &imi);
    pf_gather8_private(V, q->j, &vjx, &vjy, &vjz, &imj);
    pf_dashpots8(dx, dy, dz, inv_d, vix, viy, viz, imi, vjx, vjy, vjz, imj, contact, &gx, &gy, &gz);
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
 * calls they cost 5% and 4% more (repulsive, N = 1e5). */
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
    const int8 near = (lane < (int8)((int)count)) & (d2 < fmax(fmax(rs * rs, PF_CONTACT2), PF_RC2));
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

/* The pair forces of a step on CPU devices, before `advance` (which adds
 * them up). Work-group w of W (one work-item each) takes particles
 * [w B, (w + 1) B), B = ceil(n / W), in order. With PF_NEWTON it sums
 * forces into its own buffer F + w * force_stride only (a few work-items,
 * one per core), so no two work-items write one word and the sums come out
 * the same on every run, and records in force_spans[w] the particles whose
 * forces it changed there (its block and the partners it wrote to, mostly
 * just past the block), so that `advance` reads and clears only those of
 * the W buffers; without, it writes its particles' forces into F.
 * On the steps that rebuild the lists, each of those particles' lists is
 * rebuilt first; build_bits keeps the overflow bit for `advance`. Rows
 * filled by birth_linked's atomics (at most 4 newcomers, in sort_rows)
 * are sorted first, so that forces sum in one order. */
__kernel __attribute__((reqd_work_group_size(1, 1, 1))) void pair_forces(
    __global const float4* X, __global const float4* V, __global const uint* counts, __global const float* slots,
    const uint cell_base, const float4 cell_origin, const float4 cell_inv, const int4 cell_dims, const uint n,
    __global uint* list, __global uint* list_count, __global float4* XREF, __global uint* build_bits,
    __global const uint* request, const uint request_read, const uint force_rebuild, __global float4* F,
    const uint force_stride, const int4 sort_rows, __global uint* inner_list, __global uint2* inner_count,
    __global float4* XPRUNE, __global uint2* spans, __global uint2* force_spans) {
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
   * gather, not two (rebuild steps at N = 1e5, rc 2.5: 40-68 to 32-43 ms) */
  pf_stencil st[2];
  st[0].cell = st[1].cell = UINT_MAX;
  uint newest = 0u;
#if PF_INNER
  /* The block's inner lists lie packed one after the other from the
   * block's first row on (a pruning writes them all, and the count and so
   * the blocks cannot change before the next: births and removals make the
   * next step prune), so the pair loop streams them. */
  __global uint* inner_next = PF_ROW(inner_list, w * per);
#endif
#if PF_NEWTON
  /* a rebuild packs the block's rows from its first PF_ROW_STRIDE words on */
  uint next_row = w * per * PF_ROW_STRIDE;
#endif
  for (uint i = w * per; i < end; ++i) {
    const float4 xi = X[i];
#if PF_NEWTON
    __global uint* row = list + (rebuild ? next_row : spans[i].x);
#else
    __global uint* row = PF_ROW(list, i);
#endif
    uint count, touching; /* touching: entries that may touch i come first (pf_prune_row) */
    if (rebuild) {
      const int4 c = pf_cell_of(xi, cell_origin, cell_inv, cell_dims);
      const uint cell = pf_cell_index(c, cell_dims);
      if (st[newest].cell != cell) {
        newest = 1u - newest;
        if (st[newest].cell != cell) pf_stencil_gather(&st[newest], counts + cell_base, slots, c, cell_dims);
      }
      uint bits = 0u;
      count = pf_build_list(i, xi, &st[newest], row, &bits);
      list_count[i] = count;
#if PF_NEWTON
      const uint room = min(count + PF_ROW_SLACK, PF_LIST_CAP);
      spans[i] = (uint2)(next_row, room);
      next_row += room;
#endif
      XREF[i] = xi;
      build_bits[i] = bits;
    } else {
      count = min(list_count[i], PF_LIST_CAP);
      const int4 newcomer = (int4)((int)i) == sort_rows; /* (PoCL makes four branches of any()) */
      if ((newcomer.x | newcomer.y | newcomer.z | newcomer.w) != 0) pf_sort_row(row, count);
    }
#if PF_INNER
    /* the pairs read the inner list, pruned from the list when due */
    __global uint* inner = inner_next;
    if (prune) {
      count = pf_prune_row(i, xi, row, count, X, inner, &touching);
      inner_count[i] = (uint2)(count, touching);
      XPRUNE[i] = xi;
    } else {
      const uint2 counts = inner_count[i];
      count = counts.x;
      touching = counts.y;
    }
    inner_next += count;
    row = inner;
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
#endif

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

/* |a|^2 of a's x, y, z by explicit fused multiply-adds, as pf_norm2_8,
 * so that the GPU form's pf_integrate and the CPU form's pf_advance8
 * round their shared steps alike whatever the compiler contracts (the
 * integration's other sums are explicit fma()s too). */
float pf_norm2(float4 a) { return fma(a.z, a.z, fma(a.y, a.y, a.x * a.x)); }
float8 pf_norm2_8(float8 x, float8 y, float8 z) { return fma(z, z, fma(y, y, x * x)); }

#if PF_GPU_FORM
/* `advance` for particle i, from its state (xi, vi), the force on it and
 * its build bits: velocity Verlet with the displacement cap, the wall
 * (sampled only where the clearance bound runs out), the new state to
 * X_out and V_out, the list requests its drift raises. Returns its record.
 * The GPU form's; the CPU form's pf_advance8 does the same 8 at a time. */
float8 pf_integrate(uint i, float4 xi, float4 vi, float4 force, uint bits, uint rebuilt, uint pairs,
                    __global float4* X_out, __global float4* V_out, PF_FIELD_ARG sdf, float4 sdf_origin, int4 sdf_dims,
                    __global uint* flags, __global float* C, __global const float4* XREF, __global uint* request,
                    uint request_raise, uint n) {
  const float ri = xi.w, inv_mi = vi.w;
  const float k = PF_DT * inv_mi;
  float4 u = (float4)(fma(k, force.x, vi.x), fma(k, force.y, vi.y), fma(k, force.z, vi.z), 0.0f) * PF_DAMP;
  /* sqrt(pf_norm2()), not length(): PoCL's length() guards against
   * overflow with branches these magnitudes never need */
  const float speed = sqrt(pf_norm2(u));
  if (speed > PF_VMAX) u *= PF_VMAX / speed; /* displacement cap: at most PF_VMAX dt a step */
  const float capped_speed = speed > PF_VMAX ? PF_VMAX : speed; /* |u| now */
  float4 xn = (float4)(fma(PF_DT, u.x, xi.x), fma(PF_DT, u.y, xi.y), fma(PF_DT, u.z, xi.z), ri);
  if (sdf_dims.w != 0) {
    float clearance = fma(-2.0f * PF_DT, capped_speed, C[i]);
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
  if (pf_norm2(xn - XREF[i]) > PF_HALF_SKIN2) atomic_or(&request[request_raise], PF_REQUEST_REBUILD);
  const float u2 = pf_norm2(u);
  return pf_record(0.5f * u2 / inv_mi, u2, pf_norm2(xn - xi), rebuilt, pairs, (bits & PF_FLAGGED_BIT) ? 1u : 0u,
                   (bits & PF_OVERFLOW_BIT) ? 1u : 0u, n);
}
#else
/* Horizontal sum and maximum of 8 lanes (fixed pairwise order). */
float pf_hsum8(float8 a) {
  const float4 b = a.lo + a.hi;
  const float2 c = b.lo + b.hi;
  return c.x + c.y;
}
uint pf_hsum8u(uint8 a) {
  const uint4 b = a.lo + a.hi;
  const uint2 c = b.lo + b.hi;
  return c.x + c.y;
}
float pf_hmax8(float8 a) {
  const float4 b = fmax(a.lo, a.hi);
  const float2 c = fmax(b.lo, b.hi);
  return fmax(c.x, c.y);
}

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

#ifndef PF_FIELD_IMAGE
/* The field's values at 8 grid indices. */
float8 pf_field_gather8(__global const float* f, int8 at) {
#if defined(PF_X86_AVX512)
  return __builtin_ia32_gather3siv8sf((float8)(0.0f), (const void*)(size_t)f, at, (uchar)0xff, 4);
#else
  int a[8];
  float v[8];
  vstore8(at, 0, a);
#pragma unroll
  for (uint l = 0; l < 8u; ++l) v[l] = f[a[l]];
  return vload8(0, v);
#endif
}
#endif

PF_DEFINE_TRILINEAR(pf_trilinear8, float8)

/* The wall field (value, and its gradient in g) at 8 points as float8
 * lanes: physics.cl pf_sdf_sample and pf_trilinear (as pf_trilinear8), the
 * corners read by gathers. With PF_FIELD_IMAGE each lane samples the
 * image on its own. */
float8 pf_field_sample8(PF_FIELD_ARG f, int4 dims, float4 origin, float8 px, float8 py, float8 pz, float8* g) {
#ifdef PF_FIELD_IMAGE
  float x[8], y[8], z[8], v[8], gx[8], gy[8], gz[8];
  vstore8(px, 0, x);
  vstore8(py, 0, y);
  vstore8(pz, 0, z);
  for (uint l = 0; l < 8u; ++l) {
    float gl[3];
    v[l] = pf_sdf_sample_image(f, dims.x, dims.y, dims.z, origin.x, origin.y, origin.z, origin.w, x[l], y[l], z[l], gl);
    gx[l] = gl[0];
    gy[l] = gl[1];
    gz[l] = gl[2];
  }
  g[0] = vload8(0, gx);
  g[1] = vload8(0, gy);
  g[2] = vload8(0, gz);
  return vload8(0, v);
#else
  const float inv_spacing = origin.w;
  const float8 gx = fmin(fmax((px - origin.x) * inv_spacing, 0.0f), (float)(dims.x - 1));
  const float8 gy = fmin(fmax((py - origin.y) * inv_spacing, 0.0f), (float)(dims.y - 1));
  const float8 gz = fmin(fmax((pz - origin.z) * inv_spacing, 0.0f), (float)(dims.z - 1));
  const int8 i = min(convert_int8(floor(gx)), dims.x - 2), j = min(convert_int8(floor(gy)), dims.y - 2),
             k = min(convert_int8(floor(gz)), dims.z - 2);
  const float8 tx = gx - convert_float8(i), ty = gy - convert_float8(j), tz = gz - convert_float8(k);
  const int sy = dims.x, sz = dims.x * dims.y;
  const int8 base = i + dims.x * (j + dims.y * k);
  const float8 v000 = pf_field_gather8(f, base), v100 = pf_field_gather8(f, base + 1);
  const float8 v010 = pf_field_gather8(f, base + sy), v110 = pf_field_gather8(f, base + (sy + 1));
  const float8 v001 = pf_field_gather8(f, base + sz), v101 = pf_field_gather8(f, base + (sz + 1));
  const float8 v011 = pf_field_gather8(f, base + (sy + sz)), v111 = pf_field_gather8(f, base + (sy + sz + 1));
  return pf_trilinear8(v000, v100, v010, v110, v001, v101, v011, v111, tx, ty, tz, (float8)(inv_spacing), g);
#endif
}

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
pf_lanes8 pf_wall8(pf_lanes8 s, int8 near, float8 r, PF_FIELD_ARG sdf, float4 sdf_origin, int4 sdf_dims) {
  float8 g[3];
  float8 phi = pf_field_sample8(sdf, sdf_dims, sdf_origin, s.px, s.py, s.pz, g);
  const float8 grid_x = (s.px - sdf_origin.x) * sdf_origin.w, grid_y = (s.py - sdf_origin.y) * sdf_origin.w,
               grid_z = (s.pz - sdf_origin.z) * sdf_origin.w;
  const int8 outside_box = grid_x < 0.0f | grid_y < 0.0f | grid_z < 0.0f | grid_x > (float)(sdf_dims.x - 1) |
                           grid_y > (float)(sdf_dims.y - 1) | grid_z > (float)(sdf_dims.z - 1);
  s.flagged = near & ((phi > 0.0f) | outside_box);
  const int8 touching = near & (phi > -r);
  if (pf_any8(touching)) {
    int8 pushing = touching;
    for (int it = 0; it < PF_WALL_ITERATIONS; ++it) {
      pushing &= phi > -r;
      const float8 gl = sqrt(pf_norm2_8(g[0], g[1], g[2]));
      pushing &= gl > 1e-20f;
      if (!pf_any8(pushing)) break;
      const float8 push = (phi + r) / gl;
      s.px = select(s.px, s.px - push * g[0], pushing);
      s.py = select(s.py, s.py - push * g[1], pushing);
      s.pz = select(s.pz, s.pz - push * g[2], pushing);
      float8 h[3];
      const float8 again = pf_field_sample8(sdf, sdf_dims, sdf_origin, s.px, s.py, s.pz, h);
      phi = select(phi, again, pushing);
      g[0] = select(g[0], h[0], pushing);
      g[1] = select(g[1], h[1], pushing);
      g[2] = select(g[2], h[2], pushing);
    }
    const float8 gl = sqrt(pf_norm2_8(g[0], g[1], g[2]));
    const int8 turn = touching & (gl > 1e-20f);
    const float8 safe_gl = select((float8)(1.0f), gl, turn);
    const float8 nx = g[0] / safe_gl, ny = g[1] / safe_gl, nz = g[2] / safe_gl;
    const float8 un = s.ux * nx + s.uy * ny + s.uz * nz;
    /* physics.cl pf_wall_velocity_change, 8 lanes */
    const float8 dv = select((float8)(0.0f), -(1.0f + PF_WALL_RESTITUTION) * un, turn & (un > 0.0f));
    s.ux += dv * nx;
    s.uy += dv * ny;
    s.uz += dv * nz;
  }
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
 * lanes cost a quarter of `advance`). PoCL runs `advance`'s work-items one
 * after the other, scalar; octets take 15% off `advance` at N = 1e5. */
float8 pf_advance8(uint i0, __global const float4* X, __global const float4* V, __global float4* X_out,
                   __global float4* V_out, PF_FIELD_ARG sdf, float4 sdf_origin, int4 sdf_dims, __global uint* flags,
                   __global float* C, __global const float4* XREF, __global const float4* XPRUNE,
                   __global uint* request, uint request_raise, uint rebuild, __global float4* F, uint force_groups,
                   uint force_stride, __global const uint2* force_spans, __global const uint* build_bits, uint n) {
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
  const float8 k = PF_DT * im;
  pf_lanes8 s;
  s.ux = fma(k, fx, vx) * PF_DAMP;
  s.uy = fma(k, fy, vy) * PF_DAMP;
  s.uz = fma(k, fz, vz) * PF_DAMP;
  const float8 speed = sqrt(pf_norm2_8(s.ux, s.uy, s.uz));
  const int8 fast = speed > PF_VMAX; /* displacement cap: at most PF_VMAX dt a step */
  const float8 scale = select((float8)(1.0f), PF_VMAX / speed, fast);
  s.ux *= scale;
  s.uy *= scale;
  s.uz *= scale;
  s.px = fma(PF_DT, s.ux, x);
  s.py = fma(PF_DT, s.uy, y);
  s.pz = fma(PF_DT, s.uz, z);
  if (sdf_dims.w != 0) {
    const float8 old_clearance = vload8(0, C + i0);
    s.clearance = fma(-2.0f * PF_DT, select(speed, (float8)(PF_VMAX), fast), old_clearance);
    const int8 near = live & (s.clearance <= 0.0f);
    if (pf_any8(near)) {
      s = pf_wall8(s, near, r, sdf, sdf_origin, sdf_dims);
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
      X_out[i0 + l] = xo[l];
      V_out[i0 + l] = vo[l];
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
                   pf_hmax8(select((float8)(0.0f), disp2, live)), rebuild && i0 == 0u ? 1u : 0u,
                   pf_hsum8u(select(none, convert_uint8(fw), live)),
                   pf_hsum8u(select(none, one, live & ((bits & PF_FLAGGED_BIT) != 0u))),
                   pf_hsum8u(select(none, one, live & ((bits & PF_OVERFLOW_BIT) != 0u))), n);
}
#endif

/* The whole update of one particle (see the top of the file), plus the
 * reductions in flight. sdf_origin = (origin, 1/spacing), sdf_dims =
 * (nx, ny, nz, has_walls). Work-items: at least one a particle (GPUs)
 * or one an octet of particles (CPU devices, pf_advance8, the last octet
 * maybe partial), and a group for each level-2 partial of the last step. L1_out / L2_out: this step's level-1
 * partials and the last step's level-2 ones; L1_prev: the last step's
 * level-1 partials (g1_prev; 0: none); L2_prev: the level-2 partials of
 * the step before (g2_prev2; 0: none), whose record goes to
 * history[slot_prev2]. On GPUs the cells and lists are used here; on CPU
 * devices pair_forces used them and left the forces in F (force_groups
 * buffers, force_stride apart; with PF_NEWTON buffer g is nonzero only
 * for the particles in force_spans[g]) and the list build's overflow bits
 * in build_bits. */
__kernel __attribute__((reqd_work_group_size(PF_WG, 1, 1))) void advance(
    __global const float4* X, __global const float4* V, __global float4* X_out, __global float4* V_out,
    __global const uint* counts, __global const float* slots, const uint cell_base, const float4 cell_origin,
    const float4 cell_inv, const int4 cell_dims, PF_FIELD_ARG sdf, const float4 sdf_origin, const int4 sdf_dims,
    __global uint* flags, __global float* C, const uint n, __global float8* L1_out, __global const float8* L1_prev,
    const uint g1_prev, __global float8* L2_out, __global const float8* L2_prev, const uint g2_prev2,
    __global float8* history, const uint slot_prev2, __global uint* list, __global uint* list_count,
    __global float4* XREF, __global uint* request, const uint request_read, const uint request_raise,
    const uint request_clear, const uint force_rebuild, __global float4* F, const uint force_groups,
    const uint force_stride, __global const uint* build_bits, __global const float4* XPRUNE,
    __global const uint2* force_spans) {
#if PF_GPU_FORM
  __local float8 part[3u * PF_WG];
  __local float8 mid[3u * PF_WG_ROOT];
#endif
  const uint i = get_global_id(0), lid = get_local_id(0), group = get_group_id(0);
  if (i == 0) request[request_clear] = 0u;
  float8 record = (float8)(0.0f);
#if !PF_GPU_FORM
  /* Work-item t takes the octet 8t..8t+7 (the last may be partial) and
   * writes level-1 record t. One item an octet: PoCL runs a group's items
   * one after the other, and idle ones cost time too. */
  const uint rebuild = force_rebuild || (request[request_read] & PF_REQUEST_REBUILD);
  if (i < (n + 7u) / 8u) {
    L1_out[i] = pf_advance8(8u * i, X, V, X_out, V_out, sdf, sdf_origin, sdf_dims, flags, C, XREF, XPRUNE, request,
                            request_raise, rebuild, F, force_groups, force_stride, force_spans, build_bits, n);
  } else if (i == 0u) {
    L1_out[0] = record; /* no particles: one empty record */
  }
#else
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
        float d2 = dot(d, d);
        const float touch2 = fmax(rs * rs, PF_CONTACT2);
        if (j == i || !(d2 < fmax(touch2, PF_RC2))) continue;
        if (d2 < PF_D_MIN * PF_D_MIN) { /* on top of each other: a fixed, antisymmetric direction */
          d = (float4)(j > i ? -PF_D_MIN : PF_D_MIN, 0.0f, 0.0f, 0.0f);
          d2 = PF_D_MIN * PF_D_MIN;
        }
        float4 f = pf_lj_force_scale(d2, PF_SIGMA2, PF_EPS, PF_EXP_A, PF_EXP_B, PF_EXP_A_HALF, PF_EXP_B_HALF, PF_RC2,
                                     PF_FORCE_CAP) * d;
        if (d2 < touch2) {
          const float4 vj = V[j];
          const float4 nrm = d * rsqrt(d2);
          float4 du = vi - vj;
          du.w = 0.0f;
          f += pf_contact_damping(dot(du, nrm), inv_mi, vj.w, PF_DASHPOT) * nrm;
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
                          XREF, request, request_raise, n);
  }
#endif
  /* the reductions: this step's level 1, the last step's level 2, the step before's record */
#if PF_GPU_FORM
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
#else
  const uint g2_prev = (g1_prev + PF_WG - 1u) / PF_WG;
  /* chunk `group` by the group's first item, so that the chunks spread over the cores */
  if (lid == 0u && group < g2_prev)
    L2_out[group] = pf_partials_serial(L1_prev, group * PF_WG, min(g1_prev, (group + 1u) * PF_WG));
  if (i == 0u && g2_prev2 > 0u) history[slot_prev2] = pf_partials_serial(L2_prev, 0u, g2_prev2);
#endif
}
