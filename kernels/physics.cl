/* physics.cl: the pair potential, the contact response and the boundary
 * field sampling as small stateless functions. Shared word for word by the
 * OpenCL kernels (PF_REAL = float, built before the step files) and by the
 * double-precision host code (kernels/physics_double.hpp includes this
 * file with PF_REAL = double for the C++ reference engine and the LAMMPS
 * engine's step), so the oracle tests compare one formula.
 * Compiles on its own as OpenCL C 1.2. */
#ifndef PF_REAL
#define PF_REAL float
#endif
#ifndef PF_FN
#define PF_FN
#endif
#ifndef PF_GLOBAL
#define PF_GLOBAL __global
#endif

/* Each rule below is written once, as a definition over the value type T
 * (and the mask type M that T's comparisons give), and instantiated for
 * every width it runs at: PF_REAL here (float in the kernels, double in
 * src/engine/reference.cpp), float8 in the CPU form's kernels (cpu_pairs.cl,
 * cpu_step.cl, field.cl). Lanes are independent: a rule's operations, and
 * so its rounding, are the same at every width. `select(a, b, c)` is
 * OpenCL's (b where c); the reference defines it for double. */

/* x^(e/2): a product loop when e is an even integer (e_half = e/2 > 0,
 * unrolled when e_half is a compile-time constant), pow otherwise. */
#define PF_DEFINE_POW_HALF(NAME, T)                                                                       \
  PF_FN T NAME(T x, PF_REAL e, int e_half) {                                                              \
    if (e_half > 0) {                                                                                     \
      T r = x;                                                                                            \
      for (int k = 1; k < e_half; ++k) r *= x;                                                            \
      return r;                                                                                           \
    }                                                                                                     \
    return pow(x, (T)((PF_REAL)0.5 * e));                                                                 \
  }
PF_DEFINE_POW_HALF(pf_pow_half, PF_REAL)

/* Pairs on top of each other: where `tiny` (the caller's test d2 <
 * d_min^2), the pair's separation d = x_i - x_j becomes a fixed,
 * antisymmetric one, (-d_min, 0, 0) where j_after_i (j's index above
 * i's) and (d_min, 0, 0) otherwise, and d2 = d_min^2; so the two
 * particles of a pair are pushed apart along x in opposite directions. */
#define PF_DEFINE_APART(NAME, T, M)                                                                       \
  PF_FN void NAME(T* dx, T* dy, T* dz, T* d2, M tiny, M j_after_i, T d_min) {                             \
    *dx = select(*dx, select(d_min, -d_min, j_after_i), tiny);                                            \
    *dy = select(*dy, (T)0, tiny);                                                                        \
    *dz = select(*dz, (T)0, tiny);                                                                        \
    *d2 = select(*d2, d_min * d_min, tiny);                                                               \
  }
PF_DEFINE_APART(pf_apart, PF_REAL, int)

/* Unequal spheres (EngineParams::max_radius above radius): every length
 * of a pair's potential and contact scales with the pair's r_i + r_j
 * against the reference pair's 2 radius, q = (r_i + r_j) / (2 radius):
 * sigma_ij = q sigma, rc_ij = q rc, rest_ij = q rest (so the contact
 * distance max(r_i + r_j, rest_ij)), and its energy with the pair's
 * volume, eps_ij = q^3 eps. So the force at a given relative overlap
 * grows as q^2 (as the force a contact carries under a packing's pressure
 * does: pressure times area) and the stiffness as q (k_ij = q k, as a
 * Hooke or Hertz contact's grows with the pair's size), so that every
 * pair of a packing under one pressure overlaps by about the same
 * fraction of its radii. (With eps fixed, as before issue 29's density
 * work, the stiffness fell as k / q^2: at 1:3.3 the largest pairs were
 * 11x softer than the smallest and overlapped far more.) The dashpot
 * keeps every pair's restitution: 2 zeta sqrt(k_ij m_eff) = dashpot
 * sqrt(q m_eff) (PF_DEFINE_CONTACT_DAMPING takes q). With masses by
 * volume (m ~ q^3) a pair's frequency sqrt(k_ij / m_eff) falls with its
 * size; only a reference sphere against a much larger one (m_eff near
 * the reference mass, not half of it) runs sqrt(q / 2) times the
 * reference pair's frequency: 1.04 at 1:3.3, 1.7 at 1:10, under the
 * step's margin (dt = tau / 200). The rules give q^2 and q from
 * rs = r_i + r_j, each exactly 1 where rs equals the reference pair's
 * rs_ref (as the caller rounds it), so that a pair of reference spheres
 * runs today's constants themselves, bit for bit. */
#define PF_DEFINE_PAIR_SCALE2(NAME, T)                                                                    \
  PF_FN T NAME(T rs, PF_REAL rs_ref, PF_REAL inv_rs_ref2) {                                               \
    return select(rs * rs * inv_rs_ref2, (T)1, rs == rs_ref);                                            \
  }
PF_DEFINE_PAIR_SCALE2(pf_pair_scale2, PF_REAL)
#define PF_DEFINE_PAIR_SCALE(NAME, T)                                                                     \
  PF_FN T NAME(T rs, PF_REAL rs_ref, PF_REAL inv_rs_ref) {                                                \
    return select(rs * inv_rs_ref, (T)1, rs == rs_ref);                                                   \
  }
PF_DEFINE_PAIR_SCALE(pf_pair_scale, PF_REAL)

/* Lennard-Jones pair of DESIGN.md with exponents a > b, for squared centre
 * distance d2 > 0 and squared cutoff rc2:
 *   u(d) = 4 eps [(sigma/d)^a - (sigma/d)^b] - u(rc)               d < rc
 *   F_i  = (4 eps / d^2) [a (sigma/d)^a - b (sigma/d)^b] (r_i - r_j)
 * PF_DEFINE_LJ_FORCE_SCALE's rule takes 1/d^2 and 1/d (the CPU form
 * computes both beside each other, a shorter chain) and returns k with
 * F_i = k (r_i - r_j) (F_j = -F_i), times the pair's energy scale e (q^3
 * for unequal spheres, 1 else), clamped so that |F_i| <= force_cap;
 * for a = 2b (12-6) as 4 eps (a sb - b) sb / d^2, two multiplies fewer
 * on the chain from d^2 to the force than the general form. POW_HALF is
 * PF_DEFINE_POW_HALF's rule at the same width. Compares, not fmin / fmax:
 * k is never NaN, and PoCL's fmin handles NaNs. */
#define PF_DEFINE_LJ_FORCE_SCALE(NAME, T, POW_HALF)                                                        \
  PF_FN T NAME(T inv_d2, T inv_d, T sigma2, PF_REAL eps, PF_REAL a, PF_REAL b, int a_half, int b_half, \
               PF_REAL force_cap, T e) {                                                                    \
    const T x = sigma2 * inv_d2;                                                                            \
    const T sb = POW_HALF(x, b, b_half);                                                                    \
    T k;                                                                                                    \
    if (b_half > 0 && a_half == 2 * b_half) {                                                               \
      k = e * (((PF_REAL)4 * eps * a * sb - (PF_REAL)4 * eps * b) * (sb * inv_d2));                         \
    } else {                                                                                                \
      const T sa = POW_HALF(x, a, a_half);                                                                  \
      k = e * ((PF_REAL)4 * eps * (a * sa - b * sb) * inv_d2);                                              \
    }                                                                                                       \
    const T k_max = force_cap * inv_d;                                                                      \
    return select(select(k, k_max, k > k_max), -k_max, k < -k_max);                                        \
  }
PF_DEFINE_LJ_FORCE_SCALE(pf_lj_force_scale_inv, PF_REAL, pf_pow_half)

/* The scale k above from d2 (0 at and beyond the cutoff rc2). */
PF_FN PF_REAL pf_lj_force_scale(PF_REAL d2, PF_REAL sigma2, PF_REAL eps, PF_REAL a, PF_REAL b, int a_half,
                                int b_half, PF_REAL rc2, PF_REAL force_cap, PF_REAL e) {
  if (d2 >= rc2) return (PF_REAL)0;
  return pf_lj_force_scale_inv((PF_REAL)1 / d2, (PF_REAL)1 / sqrt(d2), sigma2, eps, a, b, a_half, b_half, force_cap,
                               e);
}

/* The pair energy u(d) above (shifted to zero at the cutoff), for d2 > 0. */
PF_FN PF_REAL pf_lj_energy(PF_REAL d2, PF_REAL sigma2, PF_REAL eps, PF_REAL a, PF_REAL b, int a_half, int b_half,
                           PF_REAL rc2) {
  if (d2 >= rc2) return (PF_REAL)0;
  const PF_REAL x = sigma2 / d2, xc = sigma2 / rc2;
  const PF_REAL u = pf_pow_half(x, a, a_half) - pf_pow_half(x, b, b_half);
  const PF_REAL uc = pf_pow_half(xc, a, a_half) - pf_pow_half(xc, b, b_half);
  return (PF_REAL)4 * eps * (u - uc);
}

/* Inelastic contact: a linear dashpot between spheres i and j while they
 * are in contact (d < max(r_i + r_j, rest distance)); n is the unit vector
 * from j to i and un = (u_i - u_j).n. The force on i is c n with
 *   c = -gamma un,  gamma = 2 zeta sqrt(k m_eff),  m_eff = 1 / (1/m_i + 1/m_j),
 * and j receives -c n, so momentum is exact. dashpot = 2 zeta sqrt(k), with
 * k the potential's stiffness at the rest distance and zeta the damping
 * ratio giving restitution e for that linearised contact:
 * zeta = -ln e / sqrt(pi^2 + ln^2 e) (0 for e = 1: no dissipation).
 * q: the pair's scale (PF_DEFINE_PAIR_SCALE; 1 for equal spheres), whose
 * stiffness is q k, so gamma = dashpot sqrt(q m_eff). Returns c. */
#define PF_DEFINE_CONTACT_DAMPING(NAME, T, INV_SQRT)                                                     \
  PF_FN T NAME(T un, T inv_mass_i, T inv_mass_j, T dashpot, T q) {                                        \
    return -dashpot * INV_SQRT((inv_mass_i + inv_mass_j) / q) * un;                                       \
  }
/* 1 / sqrt(x) as the scalar forms round it (the CPU form: x86.cl pf_rsqrt8). */
PF_FN PF_REAL pf_inv_sqrt(PF_REAL x) { return sqrt((PF_REAL)1 / x); }
PF_DEFINE_CONTACT_DAMPING(pf_contact_damping, PF_REAL, pf_inv_sqrt)

/* Wall response: with outward unit normal n and un = u.n, a sphere moving
 * outwards (un > 0) gets u += s n with s = -(1 + e_wall) un, so its normal
 * velocity becomes -e_wall un. Returns s (0 when moving inwards). */
#define PF_DEFINE_WALL_VELOCITY_CHANGE(NAME, T)                                                           \
  PF_FN T NAME(T un, T wall_restitution) {                                                                \
    return select((T)0, -((T)1 + wall_restitution) * un, un > (T)0);                                      \
  }
PF_DEFINE_WALL_VELOCITY_CHANGE(pf_wall_velocity_change, PF_REAL)

/* Whether any lane of a mask is set: for one lane, the value itself. */
#define PF_ANY1(m) (m)

/* The wall push: a sphere of radius r at p whose field value phi (signed
 * distance, negative inside) and gradient g say it reaches the surface
 * (phi > -r, the `touching` lanes) is moved along -g by (phi + r) / |g|
 * and the field sampled again, up to PF_WALL_ITERATIONS times while it
 * still reaches it; then its outward normal velocity is reflected
 * (PF_DEFINE_WALL_VELOCITY_CHANGE's rule, WALL_CHANGE, at the same width).
 * A lane whose |g| is below 1e-20 is left where it is. Updates p, u, g;
 * returns phi at the new p. SAMPLE(x, y, z, g) samples the field at the
 * width (it may use the trailing parameters, the field's); ANY is any-lane. */
#define PF_DEFINE_WALL_PUSH(NAME, T, M, ANY, SAMPLE, WALL_CHANGE, ...)                                     \
  PF_FN T NAME(T* px, T* py, T* pz, T* ux, T* uy, T* uz, T phi, T* g, M touching, T r, T wall_restitution,  \
               __VA_ARGS__) {                                                                              \
    if (!ANY(touching)) return phi;                                                                        \
    M pushing = touching;                                                                                  \
    for (int it = 0; it < PF_WALL_ITERATIONS; ++it) {                                                      \
      pushing &= phi > -r;                                                                                 \
      const T gl = sqrt(fma(g[2], g[2], fma(g[1], g[1], g[0] * g[0])));                                     \
      pushing &= gl > (T)1e-20f;                                                                           \
      if (!ANY(pushing)) break;                                                                            \
      const T push = (phi + r) / gl;                                                                       \
      *px = select(*px, *px - push * g[0], pushing);                                                       \
      *py = select(*py, *py - push * g[1], pushing);                                                       \
      *pz = select(*pz, *pz - push * g[2], pushing);                                                       \
      T h[3];                                                                                              \
      const T again = SAMPLE(*px, *py, *pz, h, pushing);                                                            \
      phi = select(phi, again, pushing);                                                                   \
      g[0] = select(g[0], h[0], pushing);                                                                  \
      g[1] = select(g[1], h[1], pushing);                                                                  \
      g[2] = select(g[2], h[2], pushing);                                                                  \
    }                                                                                                      \
    const T gl = sqrt(fma(g[2], g[2], fma(g[1], g[1], g[0] * g[0])));                                       \
    const M turn = touching & (gl > (T)1e-20f);                                                            \
    const T safe_gl = select((T)1, gl, turn);                                                              \
    const T nx = g[0] / safe_gl, ny = g[1] / safe_gl, nz = g[2] / safe_gl;                                 \
    const T un = *ux * nx + *uy * ny + *uz * nz;                                                           \
    const T dv = select((T)0, WALL_CHANGE(un, wall_restitution), turn);                                    \
    *ux += dv * nx;                                                                                        \
    *uy += dv * ny;                                                                                        \
    *uz += dv * nz;                                                                                        \
    return phi;                                                                                            \
  }

/* Integration (leapfrog with half-step velocities) of one particle before
 * the wall: u = (u + dt F / m) damp, capped at speed vmax (a displacement
 * of at most vmax dt a step), then p += dt u; explicit fma()s, so that
 * every form rounds alike whatever its compiler contracts. Takes u and p,
 * returns the speed before the cap. */
#define PF_DEFINE_KICK_DRIFT(NAME, T)                                                                     \
  PF_FN T NAME(T* ux, T* uy, T* uz, T* px, T* py, T* pz, T fx, T fy, T fz, T inv_mass, T dt, T damp,      \
               T vmax) {                                                                                  \
    const T k = dt * inv_mass;                                                                            \
    *ux = fma(k, fx, *ux) * damp;                                                                         \
    *uy = fma(k, fy, *uy) * damp;                                                                         \
    *uz = fma(k, fz, *uz) * damp;                                                                         \
    const T speed = sqrt(fma(*uz, *uz, fma(*uy, *uy, *ux * *ux)));                                        \
    const T scale = select((T)1, vmax / speed, speed > vmax);                                             \
    *ux *= scale;                                                                                         \
    *uy *= scale;                                                                                         \
    *uz *= scale;                                                                                         \
    *px = fma(dt, *ux, *px);                                                                              \
    *py = fma(dt, *uy, *py);                                                                              \
    *pz = fma(dt, *uz, *pz);                                                                              \
    return speed;                                                                                         \
  }
PF_DEFINE_KICK_DRIFT(pf_kick_drift, PF_REAL)

/* FIRE, the minimiser of Bitzek et al. (PRL 97, 170201, 2006), with the
 * half-step back-up at a restart of Guenole et al. (Comput. Mater. Sci.
 * 175, 109584, 2020), as an engine runs it (EngineParams::fire): every
 * step, one particle by PF_DEFINE_FIRE_KICK_DRIFT's rule with the step dt
 * and the mixing share alpha of the FIRE state; the state by
 * pf_fire_next from each step's power P = sum F.v, which the engine sums
 * with the step's other records and so knows a few steps late (see
 * common.cl: the record of step t is complete in step t + 2, which sets
 * the state of step t + 3). Mixing is per particle, v_i <- (1 - alpha)
 * v_i + alpha |v_i| F_i / |F_i|: Bitzek's global |v| / |F| would need two
 * more sums, known only as late as P. */
typedef struct {
  PF_REAL dt;        /* the step */
  PF_REAL alpha;     /* the mixing share */
  PF_REAL backtrack; /* at a restart, each centre moves back by this times its velocity (half the last step) */
  PF_REAL positive;  /* steps in a row with P > 0 */
  PF_REAL restarts;  /* restarts so far (for reports) */
  uint restart_step; /* the step that restarts: v = 0 after the back-up */
} pf_fire_state;

/* FIRE's schedule: dt grows by `grow` up to dt_max after `delay` steps in
 * a row with P > 0 (alpha then shrinks by alpha_shrink); at P <= 0 dt
 * shrinks by `shrink` (not below dt_min), alpha returns to alpha_start and
 * the particles restart. */
typedef struct {
  PF_REAL dt_max, dt_min, grow, shrink, alpha_start, alpha_shrink;
  PF_REAL delay;
} pf_fire_rule;

/* The state after the record of step `record_step` (power P), for the
 * steps from `effect_step` on (the first a restart can reach). A record
 * taken at or before the last restart (whose velocities the restart
 * dropped) is passed over. */
PF_FN pf_fire_state pf_fire_next(pf_fire_state s, pf_fire_rule r, PF_REAL power, uint record_step,
                                 uint effect_step) {
  if (record_step <= s.restart_step) return s;
  if (power > (PF_REAL)0) {
    s.positive += (PF_REAL)1;
    if (s.positive > r.delay) {
      s.dt = fmin(s.dt * r.grow, r.dt_max);
      s.alpha *= r.alpha_shrink;
    }
  } else {
    s.positive = (PF_REAL)0;
    s.backtrack = (PF_REAL)0.5 * s.dt;
    s.dt = fmax(s.dt * r.shrink, r.dt_min);
    s.alpha = r.alpha_start;
    s.restart_step = effect_step;
    s.restarts += (PF_REAL)1;
  }
  return s;
}

/* One particle's FIRE step (semi-implicit Euler, as FIRE 2.0): its power
 * F.u from the velocity it comes with (into *power); where `restart`, the
 * centre moved back by backtrack u and u = 0; then u += dt F / m, mixed
 * towards F (u = (1 - alpha) u + alpha |u| F / |F|, nothing where F = 0),
 * capped at speed vmax, and p += dt u. Returns the speed before the cap. */
#define PF_DEFINE_FIRE_KICK_DRIFT(NAME, T, M)                                                             \
  PF_FN T NAME(T* ux, T* uy, T* uz, T* px, T* py, T* pz, T fx, T fy, T fz, T inv_mass, T dt, T alpha,      \
               M restart, T backtrack, T vmax, T* power) {                                                \
    *power = fma(fz, *uz, fma(fy, *uy, fx * *ux));                                                        \
    *px = select(*px, fma(-backtrack, *ux, *px), restart);                                                \
    *py = select(*py, fma(-backtrack, *uy, *py), restart);                                                \
    *pz = select(*pz, fma(-backtrack, *uz, *pz), restart);                                                \
    *ux = select(*ux, (T)0, restart);                                                                     \
    *uy = select(*uy, (T)0, restart);                                                                     \
    *uz = select(*uz, (T)0, restart);                                                                     \
    const T k = dt * inv_mass;                                                                            \
    *ux = fma(k, fx, *ux);                                                                                \
    *uy = fma(k, fy, *uy);                                                                                \
    *uz = fma(k, fz, *uz);                                                                                \
    const T f2 = fma(fz, fz, fma(fy, fy, fx * fx));                                                       \
    const T v = sqrt(fma(*uz, *uz, fma(*uy, *uy, *ux * *ux)));                                            \
    const M pulled = f2 > (T)0;                                                                           \
    const T w = select((T)0, alpha * v / sqrt(select((T)1, f2, pulled)), pulled);                         \
    const T keep = select((T)1, (T)1 - alpha, pulled);                                                    \
    *ux = fma(w, fx, keep * *ux);                                                                         \
    *uy = fma(w, fy, keep * *uy);                                                                         \
    *uz = fma(w, fz, keep * *uz);                                                                         \
    const T speed = sqrt(fma(*uz, *uz, fma(*uy, *uy, *ux * *ux)));                                        \
    const T scale = select((T)1, vmax / speed, speed > vmax);                                             \
    *ux *= scale;                                                                                         \
    *uy *= scale;                                                                                         \
    *uz *= scale;                                                                                         \
    *px = fma(dt, *ux, *px);                                                                              \
    *py = fma(dt, *uy, *py);                                                                              \
    *pz = fma(dt, *uz, *pz);                                                                              \
    return speed;                                                                                         \
  }
PF_DEFINE_FIRE_KICK_DRIFT(pf_fire_kick_drift, PF_REAL, int)

/* Trilinear interpolation of one grid cell's corner values vIJK (I, J, K
 * the offsets along x, y, z) at fractions (tx, ty, tz), and in g[0..2] the
 * exact gradient of the interpolant. Shared by every way of reading the
 * corners (buffer, image), so all give the same value and gradient; as a
 * definition over the value type T, so that field.cl's 8-lane sample
 * (T = float8) has the same formula too. */
#define PF_DEFINE_TRILINEAR(NAME, T)                                                                      \
  PF_FN T NAME(T v000, T v100, T v010, T v110, T v001, T v101, T v011, T v111, T tx, T ty, T tz,          \
               T inv_spacing, T* g) {                                                                     \
    const T a00 = v000 + (v100 - v000) * tx, a10 = v010 + (v110 - v010) * tx;                             \
    const T a01 = v001 + (v101 - v001) * tx, a11 = v011 + (v111 - v011) * tx;                             \
    const T b0 = a00 + (a10 - a00) * ty, b1 = a01 + (a11 - a01) * ty;                                     \
    const T dx0 = (v100 - v000) + ((v110 - v010) - (v100 - v000)) * ty;                                   \
    const T dx1 = (v101 - v001) + ((v111 - v011) - (v101 - v001)) * ty;                                   \
    g[0] = (dx0 + (dx1 - dx0) * tz) * inv_spacing;                                                        \
    g[1] = ((a10 - a00) + ((a11 - a01) - (a10 - a00)) * tz) * inv_spacing;                                \
    g[2] = (b1 - b0) * inv_spacing;                                                                       \
    return b0 + (b1 - b0) * tz;                                                                           \
  }
PF_DEFINE_TRILINEAR(pf_trilinear, PF_REAL)

/* A sample of the wall's field as the kernels read it: with PF_WALL_OFFSET
 * (EngineParams::wall_offset) the wall moved in by that much, added to each
 * sample as it is read (the same float sum as a shifted copy would hold), so
 * a moved wall needs no second copy of the field. */
#ifdef PF_WALL_OFFSET
#define PF_SDF_AT(values, at) ((values)[at] + PF_WALL_OFFSET)
#else
#define PF_SDF_AT(values, at) ((values)[at])
#endif

/* Trilinear sample of the signed distance grid (values[i + nx (j + ny k)] at
 * origin + spacing (i, j, k); negative inside) at point p, and in g[0..2] the
 * exact gradient of the trilinear interpolant. Points outside the grid take
 * the value at the nearest grid point of the box. Needs nx, ny, nz >= 2. */
PF_FN PF_REAL pf_sdf_sample(PF_GLOBAL const float* values, int nx, int ny, int nz, PF_REAL ox, PF_REAL oy,
                            PF_REAL oz, PF_REAL inv_spacing, PF_REAL px, PF_REAL py, PF_REAL pz, PF_REAL* g) {
  const PF_REAL gx = fmin(fmax((px - ox) * inv_spacing, (PF_REAL)0), (PF_REAL)(nx - 1));
  const PF_REAL gy = fmin(fmax((py - oy) * inv_spacing, (PF_REAL)0), (PF_REAL)(ny - 1));
  const PF_REAL gz = fmin(fmax((pz - oz) * inv_spacing, (PF_REAL)0), (PF_REAL)(nz - 1));
  const int i = min((int)floor(gx), nx - 2), j = min((int)floor(gy), ny - 2), k = min((int)floor(gz), nz - 2);
  const PF_REAL tx = gx - (PF_REAL)i, ty = gy - (PF_REAL)j, tz = gz - (PF_REAL)k;
  const int base = i + nx * (j + ny * k), sy = nx, sz = nx * ny;
  const PF_REAL v000 = PF_SDF_AT(values, base), v100 = PF_SDF_AT(values, base + 1);
  const PF_REAL v010 = PF_SDF_AT(values, base + sy), v110 = PF_SDF_AT(values, base + sy + 1);
  const PF_REAL v001 = PF_SDF_AT(values, base + sz), v101 = PF_SDF_AT(values, base + sz + 1);
  const PF_REAL v011 = PF_SDF_AT(values, base + sy + sz), v111 = PF_SDF_AT(values, base + sy + sz + 1);
  return pf_trilinear(v000, v100, v010, v110, v001, v101, v011, v111, tx, ty, tz, inv_spacing, g);
}
