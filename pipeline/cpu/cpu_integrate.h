#pragma once
// The CPU backend's integrate, one row of voxels at a time and four voxels at once where GCC's generic
// vectors map to SIMD (SSE2 on x86-64). Each lane makes the same float operations in the same order as
// kernels/volume.h's integrateVoxel(), so the volume ends bit-identical to the per-voxel kernel; the kernel
// stays the reference (and the OpenCL code).

#include <cstdint>

#include "kernels/common.h"

namespace sb {

// integrateVoxel() for voxels x in [x0, x1) of one row: `row` points at the row's first physical voxel (two
// int16 per voxel), logical voxel x is stored at physical x + delta (kernels/volume.h's cyclic buffer; 0 for a
// fixed volume; [x0 + delta, x1 + delta) lies inside the row), its centre in the camera frame is
// base + step * x (metres). The other arguments are integrateVoxel()'s.
void integrateRow(int16_t* row, int delta, int x0, int x1, float3 base, float3 step, const float* depth, int width,
                  int height, SbCamera k, float mu, int maxWeight);

}  // namespace sb
