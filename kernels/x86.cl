/* x86.cl: the CPU form's 8-lane helpers (after common.cl): clang's x86
 * builtins where PoCL compiles for x86, with plain OpenCL C fallbacks;
 * lane transposes, horizontal sums. */
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


