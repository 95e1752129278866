// A tiny kernel the device-layer tests build and run: y[i] = SCALE * x[i].
// SCALE comes from the program prelude; the default keeps the file
// compilable on its own.
#ifndef SCALE
#define SCALE 1.0f
#endif

__kernel void scale_values(__global const float* x, __global float* y, const uint n) {
  const uint i = get_global_id(0);
  if (i < n) y[i] = SCALE * x[i];
}
