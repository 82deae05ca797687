#pragma once
// The CPU backend's raycast: kernels/raycast.h's sbRaycastPixel with empty-space skipping by block distance,
// rewritten for the CPU (SSE2 on x86-64, NEON on armhf, plain C++ elsewhere). Per ray it takes the same
// samples, makes the same decisions and computes every value with the same float operations in the same
// order, so the maps are bit-identical to sbRaycastPixel's (armhf: NEON flushes denormals to zero, which no
// value of the vector paths can be; see cpu_raycast.cpp). What differs is how the work is scheduled: the
// trilinear interpolation and the gradient read the voxels with a few vector loads and blend 4 lanes at a
// time, the block-distance lookup and the ray setup are vectorised, and since each ray's march is a chain of
// dependent operations (a skip's lookup decides the next sample), 4 rays are marched in turn so that their
// chains overlap. kernels/raycast.h stays the reference (the OpenCL backend runs it unchanged).

#include <cstdint>

#include "kernels/volume.h"

namespace sb {

// One raycast: the volume, its skipping structure and the march parameters of sbRaycastPixel.
struct RaycastInputs {
  const int16_t* volume = nullptr;  // resolution^3 (tsdf, weight) pairs, kernels/volume.h's layout
  int resolution = 0;               // voxels per side
  SbVoxelOffset offset{};           // the moving volume's cyclic offset (kernels/volume.h); 0 for a fixed volume
  float size = 0.0f;                // metres per side
  // pipeline/block_distance.h's distances for blocks of (1 << distanceShift)^3 voxels; nullptr: no skipping.
  const uint8_t* blockDistance = nullptr;
  int distanceShift = 0;
  // pipeline/ray_bounds.h's tMin, tMax per tile of SB_RAY_BOUNDS_TILE^2 pixels (boundsColumns per row); nullptr:
  // none (kernels/raycast.h's raycast).
  const float* rayBounds = nullptr;
  int boundsColumns = 0;
  SbMat34 cameraToWorld{};
  SbCamera camera{};                // intrinsics of the output maps
  float nearPlane = 0.0f;           // metres (depth along the camera's z axis)
  float farPlane = 0.0f;            // metres
  float largeStep = 0.0f;           // metres
  float smallStep = 0.0f;           // metres
  float smallStepBelow = 0.0f;      // tsdf (in [-1, 1]) under which the small step is used
};

// raycast of the pixels [x0, x1) x [y0, y1) into `vertex` and `normal` (3 floats per pixel, rows of `width`
// pixels): the surface point and unit normal in the volume frame, or 0 and an invalid normal
// (SB_INVALID_NORMAL), exactly as kernels/raycast.h's raycast writes them. Returns the steps the marches took.
struct RaycastWork {
  long long samples = 0;  // interpolations (the gradient's not counted)
  long long lookups = 0;  // lookups of the skipping grid
};
RaycastWork raycastRect(const RaycastInputs& in, float* vertex, float* normal, int width, int x0, int x1, int y0, int y1);

}  // namespace sb
