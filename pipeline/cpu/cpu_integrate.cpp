#include "pipeline/cpu/cpu_integrate.h"

#include <cmath>
#include <cstring>

#include "kernels/volume.h"
#include "pipeline/cpu/simd4.h"

namespace sb {

namespace {

// Four lanes as GCC generic vectors, the one exception to the four-lane layer (simd4.h): its AVX2 clone
// (SB_SIMD_CLONES below) gains from them, and on armhf GCC lowers them to scalar VFP, which is exact where
// NEON would flush denormals. One IEEE operation per lane and operator, never contracted
// (-ffp-contract=off), so every lane computes what kernels/volume.h's integrateVoxel computes
// (tests/pipeline/cpu/test_cpu_integrate.cpp checks the bits). This hand-vectorised row stays for speed: GCC
// does not vectorise the scalar kernel.
typedef float F4 __attribute__((vector_size(16)));
typedef int32_t I4 __attribute__((vector_size(16)));  // lane masks are all ones (true) or 0

inline F4 splat(float s) { return F4{s, s, s, s}; }
inline I4 splatInt(int32_t s) { return I4{s, s, s, s}; }

// integrateVoxel() for the four voxels x .. x + 3 of `row` (all in [x0, x1)), stored at x + delta ...
inline void integrateFour(int16_t* row, int x, int delta, float3 base, float3 step, const float* depth, int width, int height,
                          SbCamera k, float mu, int maxWeight) {
  const F4 xs = __builtin_convertvector((I4{x, x + 1, x + 2, x + 3}), F4);
  // base + step * x, per component (float3's operator* then operator+).
  const F4 px = splat(base.x) + splat(step.x) * xs;
  const F4 py = splat(base.y) + splat(step.y) * xs;
  const F4 pz = splat(base.z) + splat(step.z) * xs;
  I4 update = pz >= splat(SB_MIN_PROJECTION_DEPTH);  // "pos.z < min" returns (pz is finite)
  const F4 pzSafe = update ? pz : splat(1.0f);        // no division by ~0 in lanes that are out
  const F4 invZ = splat(1.0f) / pzSafe;
  // u = floor(q): floor(q) lies in [0, width - 1] exactly when q lies in [0, width), and there truncation is
  // floor; same for v.
  const F4 qu = splat(k.fx) * px * invZ + splat(k.cx) + splat(0.5f);
  const F4 qv = splat(k.fy) * py * invZ + splat(k.cy) + splat(0.5f);
  update &= (qu >= splat(0.0f)) & (qu < splat((float)width)) & (qv >= splat(0.0f)) & (qv < splat((float)height));
  const I4 u = __builtin_convertvector(update ? qu : splat(0.0f), I4);
  const I4 v = __builtin_convertvector(update ? qv : splat(0.0f), I4);
  const I4 pixel = v * splatInt(width) + u;
  const F4 d{depth[pixel[0]], depth[pixel[1]], depth[pixel[2]], depth[pixel[3]]};
  update &= d > splat(0.0f);
  if (!(update[0] | update[1] | update[2] | update[3])) return;
  // Signed distance: 1 where the depth difference is at least mu, else along the ray, capped at 1.
  const F4 alongZ = d - pz;
  // Behind the surface by mu along z is behind it by mu along the ray (the ray factor is >= 1): the test
  // below drops these lanes too; dropping them here first lets rows behind the surface stop early.
  update &= alongZ > splat(-mu);
  if (!(update[0] | update[1] | update[2] | update[3])) return;
  const I4 near = alongZ < splat(mu);
  const F4 qx = px * invZ;
  const F4 qy = py * invZ;
  const F4 lengthSquared = splat(1.0f) + qx * qx + qy * qy;
  const F4 rayFactor{sqrtf(lengthSquared[0]), sqrtf(lengthSquared[1]), sqrtf(lengthSquared[2]),
                     sqrtf(lengthSquared[3])};
  const F4 diff = alongZ * rayFactor;
  update &= ~(near & (diff <= splat(-mu)));
  const F4 ratio = diff / splat(mu);
  const F4 sdf = near ? (splat(1.0f) < ratio ? splat(1.0f) : ratio) : splat(1.0f);  // sbFmin(1, diff / mu)
  // The four voxels: int16 pairs (tsdf, weight), little end first.
  int16_t* voxels = row + 2 * (x + delta);
  I4 packed;
  memcpy(&packed, voxels, sizeof packed);
  const I4 oldTsdfRaw = (packed << 16) >> 16;  // arithmetic shifts: the sign-extended low halves
  const I4 oldWeight = packed >> 16;
  const F4 oldTsdf = __builtin_convertvector(oldTsdfRaw, F4) / splat(SB_TSDF_SCALE);
  const I4 nextWeight = oldWeight + splatInt(1);
  F4 tsdf = (__builtin_convertvector(oldWeight, F4) * oldTsdf + sdf) / __builtin_convertvector(nextWeight, F4);
  tsdf = tsdf < splat(-1.0f) ? splat(-1.0f) : (tsdf > splat(1.0f) ? splat(1.0f) : tsdf);  // sbClampFloat
  const F4 scaled = tsdf * splat(SB_TSDF_SCALE);
  const I4 stored =
      __builtin_convertvector(scaled >= splat(0.0f) ? scaled + splat(0.5f) : scaled - splat(0.5f), I4);
  const I4 weight = nextWeight < splatInt(maxWeight) ? nextWeight : splatInt(maxWeight);
  const I4 result = (stored & splatInt(0xffff)) | (weight << 16);
  packed = update ? result : packed;
  memcpy(voxels, &packed, sizeof packed);
}

}  // namespace

// Built for AVX2 too (SB_SIMD_CLONES, simd4.h): 8% less integrate time, measured; the four-lane arithmetic
// is the same IEEE operations either way.
SB_SIMD_CLONES void integrateRow(int16_t* row, int delta, int x0, int x1, float3 base, float3 step, const float* depth,
                                 int width, int height, SbCamera k, float mu, int maxWeight) {
  int x = x0;
  for (; x + 4 <= x1; x += 4) integrateFour(row, x, delta, base, step, depth, width, height, k, mu, maxWeight);
  for (; x < x1; ++x)
    integrateVoxel(row, x + delta, base + step * static_cast<float>(x), depth, width, height, k, mu, maxWeight);
}

}  // namespace sb
