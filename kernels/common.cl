/* common.cl: what both step forms share, as OpenCL C 1.2: the prelude's
 * defaults, the bits a step sets, the per-step records and their sums.
 * The engine builds one program a step form from a list of files
 * (src/engine/step_form.cpp): physics.cl, this file, then the cells, the
 * form's lists, births and removals, the field, and the form's step
 * (cpu_pairs.cl + cpu_step.cl, or gpu_step.cl). A prelude of #defines (the
 * constants below; src/engine/engine.cpp writes them) comes first; the
 * defaults here only let the files compile without it.
 *
 * State (float4 per particle): X = (position, radius), V = (velocity at the
 * half step, 1 / mass). The update is `advance`: it reads X and V and
 * writes X' and V', on GPUs the other halves of ping-pong buffers, so no
 * work-item reads what another writes; on CPU devices, where `advance`
 * reads only its own particle, the same buffers (in place). On GPUs it
 * computes the pair forces itself; on CPU devices a launch of
 * `pair_forces` before it does (cpu_pairs.cl). Leapfrog (velocity Verlet
 * written with half-step velocities):
 * u(t+1/2) = u(t-1/2) + dt F(x(t), u(t-1/2))/m, F the pair forces plus the
 * contact dashpots, x(t+1) = x(t) + dt u(t+1/2), then the wall.
 *
 * Per-step scalars (kinetic energy, speeds, counts: one float8 record a
 * particle, pf_record_merge combines two) are reduced without a launch of
 * their own, in a fixed order (so the same run gives the same sums), over
 * three steps: step t makes level-1 partials (L1), step t+1 sums chunks of
 * PF_WG of them into level-2 partials (L2), and step t+2 sums those into
 * the HISTORY record of step t: kinetic energy, max speed^2, max
 * displacement^2, lists rebuilt (0/1; under FIRE the power instead), then
 * as uints: colliding pairs, flagged particles, cell-overflow hits,
 * particle count. The work-item that writes step t's record in step t + 2
 * also writes FIRE's state for step t + 3 (pf_fire_after), so that FIRE
 * costs no launch and no transfer: it acts three steps late. On GPUs
 * (gpu_step.cl) L1 holds one sum a work-group, made in local memory, and
 * the chunk and final sums are group sums too (two levels: PF_WG_ROOT
 * items sum PF_WG / PF_WG_ROOT records each, then one item sums theirs).
 * On CPU devices (cpu_step.cl) L1 holds a record for each octet of
 * particles (8 consecutive, the first at a multiple of 8, the last maybe
 * partial); chunk c is the serial sum of group c's first item, and
 * work-item 0 sums the L2 partials: no barrier, which PoCL pays for in
 * loop overhead. finalize_history finishes the (at most two) steps still
 * in flight by the same sums. */
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

#ifndef PF_FIRE
#define PF_FIRE 0
#define PF_STEP_CAP 0.05f
#define PF_FIRE_DT_MAX 0.01f
#define PF_FIRE_DT_MIN 0.0001f
#define PF_FIRE_GROW 1.1f
#define PF_FIRE_SHRINK 0.5f
#define PF_FIRE_ALPHA_START 0.1f
#define PF_FIRE_ALPHA_SHRINK 0.99f
#define PF_FIRE_DELAY 5.0f
#endif

#ifndef PF_POLY
#define PF_POLY 0
#define PF_RS_REF 1.0f
#define PF_INV_RS_REF2 1.0f
#define PF_INV_RS_REF 1.0f
#define PF_REACH_REF 1.0f
#define PF_SKIN 0.2f
#endif

/* A pair's scale squared q^2 (physics.cl PF_DEFINE_PAIR_SCALE2) and its
 * scale q (PF_DEFINE_PAIR_SCALE: the energy's q^3 and the dashpot) from its
 * r_i + r_j: with unequal spheres (PF_POLY: EngineConstants::polydisperse)
 * the rule, exactly 1 for two reference spheres; with equal ones the
 * constant 1, which the compiler folds away (x * 1 is x), so that equal
 * spheres run the very code and constants they ran before. */
#if PF_POLY
#define PF_PAIR_Q2(rs) pf_pair_scale2(rs, PF_RS_REF, PF_INV_RS_REF2)
#define PF_PAIR_Q(rs) pf_pair_scale(rs, PF_RS_REF, PF_INV_RS_REF)
#else
#define PF_PAIR_Q2(rs) 1.0f
#define PF_PAIR_Q(rs) 1.0f
#endif

/* Whether a candidate at squared distance d2 with r_i + r_j = rs belongs
 * in a neighbour list: within PF_RL2 (the largest pair's reach plus the
 * skin) and, with unequal spheres, within its own pair's reach plus the
 * skin, max(q max(rc, rest), r_i + r_j) + skin (q = rs / (2 radius)), so
 * that a small sphere's list does not hold every small one in a large
 * pair's reach. (1 + 1e-5: the rounding of the square, on the safe side.) */
#if PF_POLY
#define PF_PAIR_REACH(rs) (fmax((rs) * (PF_INV_RS_REF * PF_REACH_REF), (rs)) + PF_SKIN)
#define PF_LISTED(d2, rs) ((d2) < PF_RL2 && (d2) < PF_PAIR_REACH(rs) * PF_PAIR_REACH(rs) * 1.00001f)
#else
#define PF_LISTED(d2, rs) ((d2) < PF_RL2)
#endif

/* Bits a step sets for a particle (pf_build_list, the wall). */
#define PF_FLAGGED_BIT 0x1u
#define PF_OVERFLOW_BIT 0x2u
/* Bits of a request word (request[]): rebuild the lists, prune the inner lists. */
#define PF_REQUEST_REBUILD 0x1u
#define PF_REQUEST_PRUNE 0x2u

/* A particle's record: (kinetic energy, speed^2, displacement^2, lists
 * rebuilt or power, then as uints: colliding pairs, flagged, cell
 * overflow, count). Squares: their maxima are the squares of the maxima,
 * so the host takes the one square root of each, not every particle. The
 * fourth is summed: in a FIRE engine (PF_FIRE) it is the particle's power
 * F.v, whose sum the FIRE state needs; otherwise 1 for the one work-item
 * that says the step rebuilt the lists and 0 for all others, so its sum
 * is that flag. */
float8 pf_record(float ke, float speed2, float disp2, float fourth, uint pairs, uint flagged, uint overflow, uint n) {
  return (float8)(ke, speed2, disp2, fourth, as_float4((uint4)(pairs, flagged, overflow, n)));
}

/* Two records as one: sums, maxima, counts summed, the particle count the larger. */
float8 pf_record_merge(float8 a, float8 b) {
  const uint4 ua = as_uint4(a.s4567), ub = as_uint4(b.s4567);
  return (float8)(a.s0 + b.s0, fmax(a.s1, b.s1), fmax(a.s2, b.s2), a.s3 + b.s3,
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
  return (float8)(a.s0 + b.s0, b.s1 > a.s1 ? b.s1 : a.s1, b.s2 > a.s2 ? b.s2 : a.s2, a.s3 + b.s3,
                  as_float4((uint4)(ua.x + ub.x, ua.y + ub.y, ua.z + ub.z, max(ua.w, ub.w))));
}

/* Partials [first, end) of src summed by one work-item in a fixed order
 * (the CPU form's chunk and final sums): four interleaved runs (k mod 4
 * from `first`, the tail in the first), added up at the end, so that the
 * kinetic energy's chain of additions is a quarter as long. */
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

/* |a|^2 of a's x, y, z by explicit fused multiply-adds, as pf_norm2_8,
 * so that the GPU form's pf_integrate and the CPU form's pf_advance8
 * round their shared steps alike whatever the compiler contracts (the
 * integration's other sums are explicit fma()s too). */
float pf_norm2(float4 a) { return fma(a.z, a.z, fma(a.y, a.y, a.x * a.x)); }
float8 pf_norm2_8(float8 x, float8 y, float8 z) { return fma(z, z, fma(y, y, x * x)); }


#if PF_FIRE
/* The FIRE state (physics.cl pf_fire_state) as the engine keeps it on the
 * device, a float8 for each of two steps in turn (step t reads fire[t % 2]
 * and its record-summing work-item writes fire[(t + 1) % 2]): (dt, alpha,
 * backtrack, positive, restarts, restart step as uint bits, 0, 0). */
pf_fire_state pf_fire_load(float8 v) {
  pf_fire_state s;
  s.dt = v.s0;
  s.alpha = v.s1;
  s.backtrack = v.s2;
  s.positive = v.s3;
  s.restarts = v.s4;
  s.restart_step = as_uint(v.s5);
  return s;
}
float8 pf_fire_save(pf_fire_state s) {
  return (float8)(s.dt, s.alpha, s.backtrack, s.positive, s.restarts, as_float(s.restart_step), 0.0f, 0.0f);
}
/* The schedule's constants (EngineParams::fire) from the prelude. */
pf_fire_rule pf_fire_rule_here(void) {
  pf_fire_rule r;
  r.dt_max = PF_FIRE_DT_MAX;
  r.dt_min = PF_FIRE_DT_MIN;
  r.grow = PF_FIRE_GROW;
  r.shrink = PF_FIRE_SHRINK;
  r.alpha_start = PF_FIRE_ALPHA_START;
  r.alpha_shrink = PF_FIRE_ALPHA_SHRINK;
  r.delay = PF_FIRE_DELAY;
  return r;
}
/* The state for the step after `step` (which read `now`), from the record
 * of step - 2 (its fourth: the power) where `have` (the steps in flight). */
float8 pf_fire_after(float8 now, float8 record, uint have, uint step) {
  pf_fire_state s = pf_fire_load(now);
  if (have) s = pf_fire_next(s, pf_fire_rule_here(), record.s3, step - 2u, step + 1u);
  return pf_fire_save(s);
}
/* finalize_history's part: the FIRE state for step step_last + 1
 * (fire[slot]) after the records of the steps in flight, the one before
 * the last (prev, where have_prev) and then the last. */
void pf_fire_finish(__global float8* fire, uint slot, uint step_last, float8 prev, uint have_prev, float8 last,
                    uint have_last) {
  pf_fire_state s = pf_fire_load(fire[slot]);
  const pf_fire_rule r = pf_fire_rule_here();
  if (have_prev) s = pf_fire_next(s, r, prev.s3, step_last - 1u, step_last + 1u);
  if (have_last) s = pf_fire_next(s, r, last.s3, step_last, step_last + 1u);
  fire[slot] = pf_fire_save(s);
}
#endif
