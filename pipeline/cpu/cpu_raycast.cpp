#include "pipeline/cpu/cpu_raycast.h"

#include <cmath>
#include <cstring>

#include "kernels/raycast.h"
#include "pipeline/cpu/simd4.h"

namespace sb {

namespace {

// The four-lane layer (simd4.h). NEON flushes denormals to zero, which changes nothing here: the
// interpolation and gradient take their vector path only 1 voxel or more inside the volume, where the weights
// f and 1 - f are multiples of 2^-23, so every product and sum of their three blending levels is a multiple
// of 2^-69 (0 or far above the denormal range); the ray's s = sOrigin + t sDirection would need a direction
// component below 1e-37 to reach it. This hand-vectorised march stays for speed beside kernels/raycast.h's
// sbRaycastPixel, which it must match bit for bit (tests/pipeline/cpu/test_cpu_raycast.cpp).
using namespace simd4;  // NOLINT: the lane layer is this file's vocabulary

inline float3 toFloat3(F4 a) { return sbMakeFloat3(lane<0>(a), lane<1>(a), lane<2>(a)); }

// The volume and its skipping structure, with the constants of the per-sample functions.
struct Volume {
  const int16_t* data;
  int resolution;
  SbVoxelOffset offset;  // cyclic (kernels/volume.h)
  bool cyclic;           // offset not 0: a cell may straddle the buffer's wrap
  int dy, dz;        // shorts from voxel (x, y, z) to (x, y + 1, z) and (x, y, z + 1)
  F4 one;            // 1 in every lane
  F4 interiorEnd;    // R - 1: interpolation cells with both corners inside
  F4 gradientEnd;    // R - 2: gradient cells whose i - 1 .. i + 2 are all inside
  const uint8_t* distance;
  int shift, blocksPerSide;
  float blockVoxels;
  explicit Volume(const RaycastInputs& in)
      : data(in.volume),
        resolution(in.resolution),
        offset(in.offset),
        cyclic(in.offset.x != 0 || in.offset.y != 0 || in.offset.z != 0),
        dy(2 * in.resolution),
        dz(2 * in.resolution * in.resolution),
        one(splat(1.0f)),
        interiorEnd(splat(float(in.resolution - 1))),
        gradientEnd(splat(float(in.resolution - 2))),
        distance(in.blockDistance),
        shift(in.distanceShift),
        blocksPerSide(in.resolution >> in.distanceShift),
        blockVoxels(float(1 << in.distanceShift)) {}
};

// sbInterpolateTsdfVoxel(s) (lanes x, y, z of s). For s in [1, R - 1) on every axis: the cell's 8 corners as
// two vectors of 4 (z = z0 and z0 + 1, each (y0, x0), (y0, x0 + 1), (y0 + 1, x0), (y0 + 1, x0 + 1)), blended
// along x, then y (4 and 2 lanes), then z; each blend is the kernel's `a * (1 - f) + b * f`. Elsewhere the
// kernel itself (its clamped border case).
// The cell's physical lower corner (cyclic buffer): the vector paths read it contiguously, so a cell whose
// reach (below, above voxels around it) crosses the buffer's wrap on some axis takes the kernel instead.
SB_HOT_INLINE bool physicalCorner(const Volume& vol, I4 i, int below, int above, int& x, int& y, int& z) {
  x = lane<0>(i);
  y = lane<1>(i);
  z = lane<2>(i);
  if (!vol.cyclic) return true;
  const int r = vol.resolution;
  x = sbWrapVoxel(x, vol.offset.x, r);
  y = sbWrapVoxel(y, vol.offset.y, r);
  z = sbWrapVoxel(z, vol.offset.z, r);
  return x >= below && y >= below && z >= below && x + above < r && y + above < r && z + above < r;
}

SB_HOT_INLINE float interpolate(const Volume& vol, F4 s) {
  if (!insideXyz(s, vol.one, vol.interiorEnd))
    return sbInterpolateTsdfVoxel(vol.data, vol.resolution, vol.offset, toFloat3(s));
  const I4 i = truncate(s);  // floor: s >= 1
  int x, y, z;
  if (!physicalCorner(vol, i, 0, 1, x, y, z))
    return sbInterpolateTsdfVoxel(vol.data, vol.resolution, vol.offset, toFloat3(s));
  const F4 f = s - toFloat(i);
  const F4 g = vol.one - f;
  const int16_t* p = vol.data + 2 * (x + y * vol.resolution + z * vol.resolution * vol.resolution);
  const F4 wx = weights0(g, f);
  const F4 c = pairSum(tsdf2x2(p, p + vol.dy) * wx, tsdf2x2(p + vol.dz, p + vol.dz + vol.dy) * wx);  // c00 c10 c01 c11
  const F4 m = c * weights1(g, f);
  const float c0 = lane<0>(m) + lane<1>(m);
  const float c1 = lane<2>(m) + lane<3>(m);
  return (c0 * lane<2>(g) + c1 * lane<2>(f)) * (1.0f / SB_TSDF_SCALE);
}

// sbTsdfGradientVoxel(s). For s in [1, R - 2) on every axis (no index is clamped): 12 loads instead of 32.
// Rows x0 - 1 .. x0 + 2 at (y, z) = (y0, z0), (y0 + 1, z0), (y0, z0 + 1), (y0 + 1, z0 + 1) hold the 8 corners
// and the x terms; 2 x 2 pairs at y0 - 1, y0 + 2 and z0 - 1, z0 + 2 the y and z terms. Each axis' 4 central
// difference blends D (along that axis), then the blend of D's pairs along the kernel's second axis, then
// along its third, in the kernel's order: gx over y then z, gy over x then z, gz over x then y.
inline float3 gradient(const Volume& vol, F4 s) {
  if (!insideXyz(s, vol.one, vol.gradientEnd))
    return sbTsdfGradientVoxel(vol.data, vol.resolution, vol.offset, toFloat3(s));
  const I4 i = truncate(s);
  int x, y, z;
  if (!physicalCorner(vol, i, 1, 2, x, y, z))
    return sbTsdfGradientVoxel(vol.data, vol.resolution, vol.offset, toFloat3(s));
  const F4 f = s - toFloat(i);
  const F4 g = vol.one - f;
  const int sy = vol.dy, sz = vol.dz;
  const int16_t* p = vol.data + 2 * (x + y * vol.resolution + z * vol.resolution * vol.resolution);
  const F4 x0 = tsdf4(p - 2), x1 = tsdf4(p - 2 + sy), x2 = tsdf4(p - 2 + sz), x3 = tsdf4(p - 2 + sy + sz);
  const F4 wx = weights0(g, f), wy = weights1(g, f), wz = weights2(g, f);
  // x: rows r = 0..3, (v(x0 + 1) - v(x0 - 1)) * (1 - fx) + (v(x0 + 2) - v(x0)) * fx.
  const F4 dx = pairSum((pick23(x0, x1) - pick01(x0, x1)) * wx, (pick23(x2, x3) - pick01(x2, x3)) * wx);
  // y: (x, z) = (0, 0), (1, 0), (0, 1), (1, 1); (c[z][1][x] - v(y0 - 1)) * (1 - fy) + (v(y0 + 2) - c[z][0][x]) * fy.
  const F4 ym = tsdf2x2(p - sy, p + sz - sy), y2 = tsdf2x2(p + 2 * sy, p + sz + 2 * sy);
  const F4 dy = (pick12(x1, x3) - ym) * broadcast<1>(g) + (y2 - pick12(x0, x2)) * broadcast<1>(f);
  // z: (x, y) = (0, 0), (1, 0), (0, 1), (1, 1).
  const F4 zm = tsdf2x2(p - sz, p - sz + sy), z2 = tsdf2x2(p + 2 * sz, p + 2 * sz + sy);
  const F4 dz = (pick12(x2, x3) - zm) * broadcast<2>(g) + (z2 - pick12(x0, x1)) * broadcast<2>(f);
  const F4 xy = pairSum(dx * wy, dy * wx);  // gx's and gy's two halves
  const F4 zz = pairSum(dz * wx, dz * wx);  // gz's two halves, twice
  const F4 r = pairSum(xy * wz, zz * wy);   // gx gy gz gz
  return toFloat3(r);
}

// sbSkipByDistance for a sample s inside [0, R - 1): the box's exit face per axis is b + d or b - d + 1
// blocks (b + (d ^ neg) - neg + (neg & 1) with neg = -1 where sInverse < 0).
struct RaySkip {
  F4 sOrigin, sInverse;
  I4 negative, negativeOne;
};
SB_HOT_INLINE float skipByDistance(const Volume& vol, const RaySkip& ray, F4 s) {
  const I4 b = shiftRight(truncate(s), vol.shift);
  const int d = vol.distance[lane<0>(b) + lane<1>(b) * vol.blocksPerSide +
                             lane<2>(b) * vol.blocksPerSide * vol.blocksPerSide];
  if (d == 0) return -1.0f;
  const I4 face = b + ((splatInt(d) ^ ray.negative) - ray.negative) + ray.negativeOne;
  return min012((toFloat(face) * splat(vol.blockVoxels) - ray.sOrigin) * ray.sInverse);
}

// One ray of sbRaycastPixel with blockDistance (or no skipping) as a state machine: start() sets it up,
// advance() makes one iteration of the kernel's march loop, finish() writes the pixel. The raycast is bound by
// the latency of each ray's chain of dependent operations (a skip's lookup decides the next sample), so
// raycastRect keeps several rays in flight and advances them in turn: their chains overlap.
struct Ray {
  F4 direction, sDirection;
  RaySkip skip;  // sOrigin, sInverse
  float tExit, lookupLo, lookupHi;
  int index;
  // The march: samples t = tBase + n * step; see sbRaycastPixel.
  float t, tBase, step, fPrevious, fCurrent;
  int n;
  int smallSteps;       // the step is smallStep
  int previousSkipped;  // the sample before the current one was left out (fPrevious is not its value)
  int lookup;           // not in the small-step band: the sample at t asks the skipping grid
  int hit;              // the march ended below 0
  int samples;          // interpolations so far (the work counters, StageWork)
  int lookups;          // lookups of the skipping grid so far
};

// One iteration of sbRaycastPixel's march loop; returns false when the march has ended. kFirst: the sample
// at t is the first one, already interpolated (fPrevious).
template <bool kFirst>
SB_HOT_INLINE bool advance(const RaycastInputs& in, const Volume& vol, Ray& r) {
  if (!(r.t < r.tExit)) return false;
  const F4 s = r.skip.sOrigin + r.sDirection * splat(r.t);
  float skipTo = -1.0f;
  // Inside the small-step band (the previous sample was taken and is below smallStepBelow) no lookup.
  if (r.lookup && r.t >= r.lookupLo && r.t < r.lookupHi) {
    skipTo = skipByDistance(vol, r.skip, s);
    ++r.lookups;
  }
  if (skipTo > r.t) {
    const float skipEnd = sbFmin(skipTo, r.tExit) - SB_SKIP_MARGIN * in.smallStep;
    // The kernel's next = (int)sbFloor(q) + 1 and n = max(next, n + 1) with the truncation instead of the
    // floor: they differ only for q < 0, where both give next <= 1 <= n + 1, so n is the same.
    const int next = (int)((skipEnd - r.tBase) / r.step) + 1;
    r.n = next > r.n + 1 ? next : r.n + 1;
    r.previousSkipped = 1;
    r.lookup = 1;
  } else {
    r.fCurrent = kFirst ? r.fPrevious : interpolate(vol, s);
    if (!kFirst) ++r.samples;
    if (!kFirst && r.fCurrent < 0.0f) {
      if (r.previousSkipped) {
        r.fPrevious = interpolate(vol, r.skip.sOrigin + r.sDirection * splat(r.tBase + (float)(r.n - 1) * r.step));
        ++r.samples;
      }
      r.hit = 1;
      return false;
    }
    if (r.fCurrent < in.smallStepBelow && !r.smallSteps) {
      r.smallSteps = 1;
      r.step = in.smallStep;
      r.tBase = r.t;
      r.n = 0;
    }
    r.fPrevious = r.fCurrent;
    r.previousSkipped = 0;
    // In the band from now on when below smallStepBelow (which has started the small steps, if not before).
    r.lookup = !(r.fCurrent < in.smallStepBelow);
    ++r.n;
  }
  r.t = r.tBase + (float)r.n * r.step;
  return true;
}

// Writes the pixel of a ray whose march has ended: the zero crossing and its normal, or no surface.
inline void finish(const Volume& vol, const Ray& r, F4 origin, float* outVertex, float* outNormal) {
  float3 vertex = sbMakeFloat3(0.0f, 0.0f, 0.0f);
  float3 normal = sbMakeFloat3(SB_INVALID_NORMAL, 0.0f, 0.0f);
  if (r.hit) {
    const float t = r.t + r.step * r.fCurrent / (r.fPrevious - r.fCurrent);
    const float3 g = gradient(vol, r.skip.sOrigin + r.sDirection * splat(t));
    const float len = sbLength(g);
    if (len > 0.0f) {
      vertex = toFloat3(origin + r.direction * splat(t));
      normal = g * (1.0f / len);
    }
  }
  sbStore3(vertex, outVertex, r.index);
  sbStore3(normal, outNormal, r.index);
}

// The camera's constants of sbRaycastPixel's setup: the ray origin in metres (o) and voxels (so), the
// numerators of its divisions, the rotation's columns. Lane 3 is not used.
struct Camera {
  SbCamera k;
  F4 rotation[3];
  F4 o, so, zeroMinusO, sizeMinusO, marginMinusSo, topMinusSo;
  float origin[3], sOrigin[3];
  float scale, margin, top;
  int outside, sOutside;  // bit a: the origin lies outside the volume's box (outside [margin, top] in voxels)
  explicit Camera(const RaycastInputs& in) : k(in.camera) {
    const SbMat34& m = in.cameraToWorld;
    for (int c = 0; c < 3; ++c) rotation[c] = make4(m.m[c], m.m[4 + c], m.m[8 + c], c == 2 ? 1.0f : 0.0f);
    scale = (float)in.resolution / in.size;
    margin = 1e-3f;  // sbVoxelRange's
    top = (float)(in.resolution - 1) - margin;
    o = make4(m.m[3], m.m[7], m.m[11], 0.0f);
    so = o * splat(scale) - splat(0.5f);
    zeroMinusO = splat(0.0f) - o;
    sizeMinusO = splat(in.size) - o;
    marginMinusSo = splat(margin) - so;
    topMinusSo = splat(top) - so;
    store4Xyz(origin, o);
    store4Xyz(sOrigin, so);
    outside = sOutside = 0;
    for (int a = 0; a < 3; ++a) {
      if (origin[a] < 0.0f || origin[a] > in.size) outside |= 1 << a;
      if (!(sOrigin[a] >= margin && sOrigin[a] <= top)) sOutside |= 1 << a;
    }
  }
  static void store4Xyz(float* out, F4 a) {
    float all[4];
    store(all, a);
    for (int i = 0; i < 3; ++i) out[i] = all[i];
  }
};

// Sets up the ray of pixel (x, y); returns false (and has written the pixel) when it has nothing to march.
// sbRaycastPixel's setup with the same operations per lane, its divisions three lanes at a time (lane 3 of
// each divides by a non-zero number and is not used).
SB_HOT_INLINE bool start(const RaycastInputs& in, const Volume& vol, const Camera& cam, Ray& r, float* outVertex,
                         float* outNormal, int width, int x, int y) {
  r.index = y * width + x;
  r.samples = 0;
  r.lookups = 0;
  // The ray bounds (pipeline/ray_bounds.h), as kernels/raycast.h's raycast reads them (x, y >= 0). A tile that no
  // surface box reaches holds tMin = +inf > tMax = -inf (any box gives tMin <= tMax): its rays march nothing.
  float tMin = -1e30f, tMax = 1e30f;
  if (in.rayBounds != nullptr) {
    const unsigned tile =
        (unsigned(y) / SB_RAY_BOUNDS_TILE) * unsigned(in.boundsColumns) + unsigned(x) / SB_RAY_BOUNDS_TILE;
    tMin = in.rayBounds[2 * tile];
    tMax = in.rayBounds[2 * tile + 1];
    if (!(tMin <= tMax)) {
      sbStore3(sbMakeFloat3(0.0f, 0.0f, 0.0f), outVertex, r.index);
      sbStore3(sbMakeFloat3(SB_INVALID_NORMAL, 0.0f, 0.0f), outNormal, r.index);
      return false;
    }
  }
  float q[4];
  store(q, make4((float)x - cam.k.cx, (float)y - cam.k.cy, 1.0f, 1.0f) / make4(cam.k.fx, cam.k.fy, 1.0f, 1.0f));
  // sbRotate(pose, (q0, q1, 1)): m0 * q0 + m1 * q1 + m2 * 1 per row (m2 * 1 is m2; lane 3 gets 1).
  const F4 d4 = cam.rotation[0] * splat(q[0]) + cam.rotation[1] * splat(q[1]) + cam.rotation[2];
  // Entry and exit of the volume's box: the kernel's loop over the axes whose direction is not 0, as lanes
  // (sbFmax and sbFmin give the same value in any order; the other axes' lanes are left out by +-inf), and
  // no exit (-1, or less in the kernel: either way no march) when an axis of direction 0 lies outside.
  const F4 t0 = cam.zeroMinusO / d4, t1 = cam.sizeMinusO / d4;
  const M4 moving = d4 != splat(0.0f);
  const float tEnter = sbFmax(in.nearPlane, max012(select(moving, min(t0, t1), splat(-INFINITY))));
  float tExit = sbFmin(in.farPlane, min012(select(moving, max(t0, t1), splat(INFINITY))));
  if (~bits012(moving) & cam.outside) tExit = -1.0f;
  tExit = sbFmin(tExit, tMax);
  if (tEnter < tExit) {
    // The ray in voxel coordinates; sInverse is 0 where the direction is 0.
    const F4 sd4 = d4 * splat(cam.scale);
    r.direction = d4;
    r.sDirection = sd4;
    r.skip.sOrigin = cam.so;
    r.skip.sInverse = keepWhereNonZero(splat(1.0f) / sd4, sd4);
    r.skip.negative = notGreaterEqualZero(r.skip.sInverse);
    r.skip.negativeOne = r.skip.negative & splatInt(1);
    const bool bounded = tMin > tEnter;  // the march skips to tMin from the first sample, not interpolated
    r.fPrevious = 1.0f;
    if (!bounded) {
      r.fPrevious = interpolate(vol, cam.so + sd4 * splat(tEnter));
      r.samples = 1;
    }
    if (r.fPrevious > 0.0f) {
      // Lookups only where s is inside [0, R - 1) (sbVoxelRange); none at all without a skipping structure.
      r.lookupLo = 1e30f;
      r.lookupHi = -1e30f;
      if (vol.distance != nullptr) {  // as the box above (-1e30 where the kernel may go lower: no lookup)
        const F4 v0 = cam.marginMinusSo / sd4, v1 = cam.topMinusSo / sd4;
        const M4 sMoving = sd4 != splat(0.0f);
        r.lookupLo = sbFmax(-1e30f, max012(select(sMoving, min(v0, v1), splat(-INFINITY))));
        r.lookupHi = sbFmin(1e30f, min012(select(sMoving, max(v0, v1), splat(INFINITY))));
        if (~bits012(sMoving) & cam.sOutside) r.lookupHi = -1e30f;
      }
      r.tExit = tExit;
      r.t = tEnter;
      r.tBase = tEnter;
      r.step = in.largeStep;
      r.fCurrent = r.fPrevious;
      r.n = 0;
      r.smallSteps = 0;
      r.previousSkipped = 0;
      r.lookup = 1;
      r.hit = 0;
      if (bounded) {
        const int next = (int)sbFloor((tMin - SB_SKIP_MARGIN * in.smallStep - r.tBase) / r.step) + 1;
        r.n = next > 1 ? next : 1;
        r.previousSkipped = 1;
        r.t = r.tBase + (float)r.n * r.step;
        return true;
      }
      // The first iteration: its sample (at tEnter, above 0) is already interpolated.
      if (advance<true>(in, vol, r)) return true;
      finish(vol, r, cam.o, outVertex, outNormal);
      return false;
    }
  }
  sbStore3(sbMakeFloat3(0.0f, 0.0f, 0.0f), outVertex, r.index);
  sbStore3(sbMakeFloat3(SB_INVALID_NORMAL, 0.0f, 0.0f), outNormal, r.index);
  return false;
}

// The rays in flight in raycastRect.
constexpr int kRaysInFlight = 4;
// raycastRect's pixel order: columns of this many pixels (neighbouring rays read neighbouring voxels).
constexpr int kTileColumns = 8;

}  // namespace

RaycastWork raycastRect(const RaycastInputs& in, float* vertex, float* normal, int width, int x0, int x1, int y0,
                        int y1) {
  RaycastWork work;
  if (x0 >= x1 || y0 >= y1) return work;
  const Volume vol(in);
  const Camera cam(in);
  // The next pixel: tiles of kTileColumns columns from the left, each row by row.
  int tileX = x0, x = x0, y = y0;
  // Starts the next pixel that has something to march in `r`; false when there is none left.
  const auto launch = [&](Ray& r) {
    while (tileX < x1) {
      const int px = x, py = y;
      if (++x == x1 || x == tileX + kTileColumns) {
        x = tileX;
        if (++y == y1) {
          y = y0;
          tileX = x = tileX + kTileColumns;
        }
      }
      if (start(in, vol, cam, r, vertex, normal, width, px, py)) return true;
      work.samples += r.samples;
      work.lookups += r.lookups;
    }
    return false;
  };
  Ray rays[kRaysInFlight];
  bool active[kRaysInFlight];
  int flying = 0;
  for (int i = 0; i < kRaysInFlight; ++i) flying += (active[i] = launch(rays[i])) ? 1 : 0;
  while (flying > 0) {
    for (int i = 0; i < kRaysInFlight; ++i) {
      if (active[i] && !advance<false>(in, vol, rays[i])) {
        finish(vol, rays[i], cam.o, vertex, normal);
        work.samples += rays[i].samples;
        work.lookups += rays[i].lookups;
        if (!(active[i] = launch(rays[i]))) --flying;
      }
    }
  }
  return work;
}

}  // namespace sb
