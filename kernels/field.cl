/* field.cl: sampling the wall's signed distance field (after common.cl,
 * and on CPU devices x86.cl): one point at a time (physics.cl
 * pf_sdf_sample, or the image's pf_sdf_sample_image) and 8 points as
 * float8 lanes, all by physics.cl's trilinear formula.
 *
 * Wall clearance: C[i] is a lower bound on how far particle i's sphere is
 * from the wall; it shrinks by 2 |dx| a step (the trilinear field changes
 * by at most sqrt(3) |dx|) and the field is sampled only when it reaches 0. */
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
#ifdef PF_WALL_OFFSET
  return read_imagef(f, pf_field_sampler, (int4)(i, j, k, 0)).x + PF_WALL_OFFSET;
#else
  return read_imagef(f, pf_field_sampler, (int4)(i, j, k, 0)).x;
#endif
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

#ifndef PF_FIELD_IMAGE
/* The field's values at 8 grid indices, read only in the `lanes` set
 * (0 in the others): an octet near the wall often has one or two lanes
 * there, and the reads, cache misses in a large field, are the cost. */
float8 pf_field_gather8_raw(__global const float* f, int8 at, int8 lanes) {
#if defined(PF_X86_AVX512)
  return __builtin_ia32_gather3siv8sf((float8)(0.0f), (const void*)(size_t)f, at, (uchar)PF_MASK8(lanes), 4);
#else
  int a[8], m[8];
  float v[8];
  vstore8(at, 0, a);
  vstore8(lanes, 0, m);
#pragma unroll
  for (uint l = 0; l < 8u; ++l) v[l] = m[l] != 0 ? f[a[l]] : 0.0f;
  return vload8(0, v);
#endif
}

/* ... with the wall's offset (physics.cl PF_SDF_AT). */
float8 pf_field_gather8(__global const float* f, int8 at, int8 lanes) {
#ifdef PF_WALL_OFFSET
  return pf_field_gather8_raw(f, at, lanes) + PF_WALL_OFFSET;
#else
  return pf_field_gather8_raw(f, at, lanes);
#endif
}
#endif

PF_DEFINE_TRILINEAR(pf_trilinear8, float8)

#ifndef PF_FIELD_IMAGE
/* The grid cell each of 8 points lies in, clamped into the grid as
 * physics.cl pf_sdf_sample does: its first corner's index (returned) and
 * the point's place in it, t[0..2] in [0, 1] along x, y, z. */
int8 pf_field_cell8(int4 dims, float4 origin, float8 px, float8 py, float8 pz, float8 t[3]) {
  const float inv_spacing = origin.w;
  const float8 gx = fmin(fmax((px - origin.x) * inv_spacing, 0.0f), (float)(dims.x - 1));
  const float8 gy = fmin(fmax((py - origin.y) * inv_spacing, 0.0f), (float)(dims.y - 1));
  const float8 gz = fmin(fmax((pz - origin.z) * inv_spacing, 0.0f), (float)(dims.z - 1));
  /* (vector bounds, not min(int8, int): oclgrind gave some lanes garbage
   * there, and those lanes read out of the field) */
  const int8 i = min(convert_int8(floor(gx)), (int8)(dims.x - 2)), j = min(convert_int8(floor(gy)), (int8)(dims.y - 2)),
             k = min(convert_int8(floor(gz)), (int8)(dims.z - 2));
  t[0] = gx - convert_float8(i);
  t[1] = gy - convert_float8(j);
  t[2] = gz - convert_float8(k);
  return i + dims.x * (j + dims.y * k);
}

/* The 8 corners of the cells whose first corners are `base`
 * (pf_field_cell8), in pf_trilinear's order, read in the `lanes` set only
 * (0 in the others). */
void pf_field_corners8(__global const float* f, int4 dims, int8 base, int8 lanes, float8 v[8]) {
  const int sy = dims.x, sz = dims.x * dims.y;
  v[0] = pf_field_gather8(f, base, lanes);
  v[1] = pf_field_gather8(f, base + 1, lanes);
  v[2] = pf_field_gather8(f, base + sy, lanes);
  v[3] = pf_field_gather8(f, base + (sy + 1), lanes);
  v[4] = pf_field_gather8(f, base + sz, lanes);
  v[5] = pf_field_gather8(f, base + (sz + 1), lanes);
  v[6] = pf_field_gather8(f, base + (sy + sz), lanes);
  v[7] = pf_field_gather8(f, base + (sy + sz + 1), lanes);
}
#endif

/* The wall field (value, and its gradient in g) at 8 points as float8
 * lanes: physics.cl pf_sdf_sample and pf_trilinear (as pf_trilinear8), the
 * corners read by gathers. With PF_FIELD_IMAGE each lane samples the
 * image on its own. Only the `lanes` set are read; the others' value and
 * gradient are meaningless (callers select them away). */
float8 pf_field_sample8(PF_FIELD_ARG f, int4 dims, float4 origin, float8 px, float8 py, float8 pz, float8* g,
                        int8 lanes) {
#ifdef PF_FIELD_IMAGE
  float x[8], y[8], z[8], v[8], gx[8], gy[8], gz[8];
  vstore8(px, 0, x);
  vstore8(py, 0, y);
  vstore8(pz, 0, z);
  int m[8];
  vstore8(lanes, 0, m);
  for (uint l = 0; l < 8u; ++l) {
    if (m[l] == 0) {
      v[l] = gx[l] = gy[l] = gz[l] = 0.0f;
      continue;
    }
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
  float8 t[3], v[8];
  pf_field_corners8(f, dims, pf_field_cell8(dims, origin, px, py, pz, t), lanes, v);
  return pf_trilinear8(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], t[0], t[1], t[2], (float8)(origin.w), g);
#endif

}
