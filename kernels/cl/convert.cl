// Map storage conversion between float and half (vload_half / vstore_half, core OpenCL 1.2): used when the
// backend switches precision between frames, and to read half maps back as float.

__kernel void halfToFloatKernel(__global float* out, __global const half* in, int count) {
  const int i = get_global_id(0);
  if (i < count) out[i] = vload_half(i, in);
}

__kernel void floatToHalfKernel(__global half* out, __global const float* in, int count) {
  const int i = get_global_id(0);
  if (i < count) vstore_half(in[i], i, out);
}
