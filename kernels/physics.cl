/* physics.cl: the pair potential, the contact response and the boundary
 * field sampling as small stateless functions. Shared word for word by the
 * OpenCL kernels (PF_REAL = float, built before the step files) and by the
 * double-precision C++ reference (src/engine/reference.cpp includes this
 * file with PF_REAL = double), so the oracle tests compare one formula.
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

/* x^(e/2): a product loop when e is an even integer (e_half = e/2 > 0,
 * unrolled when e_half is a compile-time constant), pow otherwise. */
PF_FN PF_REAL pf_pow_half(PF_REAL x, PF_REAL e, int e_half) {
  if (e_half > 0) {
    PF_REAL r = x;
    for (int k = 1; k < e_half; ++k) r *= x;
    return r;
  }
  return pow(x, (PF_REAL)0.5 * e);
}

/* Lennard-Jones pair of DESIGN.md with exponents a > b, for squared centre
 * distance d2 > 0 and squared cutoff rc2:
 *   u(d) = 4 eps [(sigma/d)^a - (sigma/d)^b] - u(rc)               d < rc
 *   F_i  = (4 eps / d^2) [a (sigma/d)^a - b (sigma/d)^b] (r_i - r_j)
 * Returns k with F_i = k (r_i - r_j) (F_j = -F_i), clamped so that
 * |F_i| <= force_cap; 0 at and beyond the cutoff. */
PF_FN PF_REAL pf_lj_force_scale(PF_REAL d2, PF_REAL sigma2, PF_REAL eps, PF_REAL a, PF_REAL b, int a_half,
                                int b_half, PF_REAL rc2, PF_REAL force_cap) {
  if (d2 >= rc2) return (PF_REAL)0;
  const PF_REAL x = sigma2 / d2;
  const PF_REAL sb = pf_pow_half(x, b, b_half);
  const PF_REAL sa = (b_half > 0 && a_half == 2 * b_half) ? sb * sb : pf_pow_half(x, a, a_half);
  const PF_REAL k = (PF_REAL)4 * eps * (a * sa - b * sb) / d2;
  const PF_REAL k_max = force_cap / sqrt(d2);
  return fmin(fmax(k, -k_max), k_max);
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
 * Returns c. */
PF_FN PF_REAL pf_contact_damping(PF_REAL un, PF_REAL inv_mass_i, PF_REAL inv_mass_j, PF_REAL dashpot) {
  return -dashpot * sqrt((PF_REAL)1 / (inv_mass_i + inv_mass_j)) * un;
}

/* Wall response: with outward unit normal n and un = u.n, a sphere moving
 * outwards (un > 0) gets u += s n with s = -(1 + e_wall) un, so its normal
 * velocity becomes -e_wall un. Returns s (0 when moving inwards). */
PF_FN PF_REAL pf_wall_velocity_change(PF_REAL un, PF_REAL wall_restitution) {
  return un > (PF_REAL)0 ? -((PF_REAL)1 + wall_restitution) * un : (PF_REAL)0;
}

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
  const PF_REAL v000 = values[base], v100 = values[base + 1];
  const PF_REAL v010 = values[base + sy], v110 = values[base + sy + 1];
  const PF_REAL v001 = values[base + sz], v101 = values[base + sz + 1];
  const PF_REAL v011 = values[base + sy + sz], v111 = values[base + sy + sz + 1];
  return pf_trilinear(v000, v100, v010, v110, v001, v101, v011, v111, tx, ty, tz, inv_spacing, g);
}
