#pragma once
// The common subset of C++17 and OpenCL C that every kernel header is written in.
//
// Rules for kernels/: plain `SB_INLINE` functions taking pointers, sizes and indices; no templates, classes,
// references, std:: or Eigen. Buffers are flat float arrays (3 floats per vertex / normal, accessed through
// SB_LOAD3 / SB_STORE3, which are vload3 / vstore3 in OpenCL) so the memory layout is identical on every
// backend. Address spaces go through SB_GLOBAL. Maths goes through the sb* helpers below (builtins in
// OpenCL, <math.h> in C++).
//
// Storage seam for the preprocessed maps (depth pyramid, vertex and normal maps): they are `sb_map_t`
// arrays accessed only through SB_LOAD_MAP / SB_STORE_MAP / SB_LOAD_MAP3 / SB_STORE_MAP3. Compiling an
// OpenCL program with -DSB_MAP_HALF stores them as half (vload_half / vstore_half, core OpenCL 1.2) while
// the arithmetic stays in float; the C++ build always stores float.

#ifdef __OPENCL_C_VERSION__

#define SB_GLOBAL __global
#define SB_INLINE static inline

#define sbMakeFloat3(x, y, z) ((float3)((x), (y), (z)))
#define sbSqrt(v) sqrt(v)
#define sbExp(v) exp(v)
#define sbFloor(v) floor(v)
#define sbFabs(v) fabs(v)
#define sbFmin(a, b) fmin((a), (b))
#define sbFmax(a, b) fmax((a), (b))
#define sbDot(a, b) dot((a), (b))
#define sbCross(a, b) cross((a), (b))
#define sbLength(a) length(a)
#define SB_LOAD3(p, i) vload3((i), (p))
#define SB_STORE3(v, p, i) vstore3((v), (i), (p))

#ifdef SB_MAP_HALF
typedef half sb_map_t;
#define SB_LOAD_MAP(p, i) vload_half((i), (p))
#define SB_STORE_MAP(v, p, i) vstore_half((v), (i), (p))
#define SB_LOAD_MAP3(p, i) vload_half3((i), (p))
#define SB_STORE_MAP3(v, p, i) vstore_half3((v), (i), (p))
#else
typedef float sb_map_t;
#define SB_LOAD_MAP(p, i) ((p)[i])
#define SB_STORE_MAP(v, p, i) ((p)[i] = (v))
#define SB_LOAD_MAP3(p, i) vload3((i), (p))
#define SB_STORE_MAP3(v, p, i) vstore3((v), (i), (p))
#endif

#else  // C++

#include <math.h>
#include <string.h>

#define SB_GLOBAL
#define SB_INLINE static inline

struct float3 {
  float x, y, z;
};
inline float3 operator+(float3 a, float3 b) { return float3{a.x + b.x, a.y + b.y, a.z + b.z}; }
inline float3 operator-(float3 a, float3 b) { return float3{a.x - b.x, a.y - b.y, a.z - b.z}; }
inline float3 operator-(float3 a) { return float3{-a.x, -a.y, -a.z}; }
inline float3 operator*(float3 a, float s) { return float3{a.x * s, a.y * s, a.z * s}; }
inline float3 operator*(float s, float3 a) { return float3{a.x * s, a.y * s, a.z * s}; }
inline float3 operator/(float3 a, float s) { return float3{a.x / s, a.y / s, a.z / s}; }

SB_INLINE float3 sbMakeFloat3(float x, float y, float z) { return float3{x, y, z}; }
SB_INLINE float sbSqrt(float v) { return sqrtf(v); }
// exp for the kernels' weights: 2^n * p(f) with a degree-6 polynomial (relative error < 2e-7 on [-87, 88]),
// inlineable and auto-vectorisable unlike the libm call. OpenCL uses the builtin.
SB_INLINE float sbExp(float v) {
  v = v < -87.0f ? -87.0f : (v > 88.0f ? 88.0f : v);
  const float t = v * 1.44269504f;                    // log2(e)
  const float n = (t + 12582912.0f) - 12582912.0f;   // round to nearest (1.5 * 2^23 trick)
  const float f = (v - n * 0.693145752f) - n * 1.42860677e-6f;  // v - n ln2, in two parts
  float p = 1.0f / 720.0f;
  p = p * f + 1.0f / 120.0f;
  p = p * f + 1.0f / 24.0f;
  p = p * f + 1.0f / 6.0f;
  p = p * f + 0.5f;
  p = p * f + 1.0f;
  p = p * f + 1.0f;
  const int bits = ((int)n + 127) << 23;
  float scale;
  memcpy(&scale, &bits, sizeof scale);
  return p * scale;
}
SB_INLINE float sbFabs(float v) { return fabsf(v); }
// floor without the libm call (baseline x86-64 and ARMv7 have no rounding instruction): truncation corrected
// for negative non-integers; |v| >= 2^23 is already an integer (and NaN passes through). Equal to floorf
// except that -0 gives +0.
SB_INLINE float sbFloor(float v) {
  if (!(sbFabs(v) < 8388608.0f)) return v;
  const float t = (float)(int)v;
  return t > v ? t - 1.0f : t;
}
SB_INLINE float sbFmin(float a, float b) { return a < b ? a : b; }
SB_INLINE float sbFmax(float a, float b) { return a > b ? a : b; }
SB_INLINE float sbDot(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
SB_INLINE float3 sbCross(float3 a, float3 b) {
  return float3{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
SB_INLINE float sbLength(float3 a) { return sqrtf(sbDot(a, a)); }
SB_INLINE float3 sbLoad3(const float* p, int i) { return float3{p[3 * i], p[3 * i + 1], p[3 * i + 2]}; }
SB_INLINE void sbStore3(float3 v, float* p, int i) {
  p[3 * i] = v.x;
  p[3 * i + 1] = v.y;
  p[3 * i + 2] = v.z;
}
#define SB_LOAD3(p, i) sbLoad3((p), (i))
#define SB_STORE3(v, p, i) sbStore3((v), (p), (i))

typedef float sb_map_t;
#define SB_LOAD_MAP(p, i) ((p)[i])
#define SB_STORE_MAP(v, p, i) ((p)[i] = (v))
#define SB_LOAD_MAP3(p, i) sbLoad3((p), (i))
#define SB_STORE_MAP3(v, p, i) sbStore3((v), (p), (i))

#endif

SB_INLINE int sbClampInt(int v, int lo, int hi) { return v < lo ? lo : (v > hi ? hi : v); }
SB_INLINE float sbClampFloat(float v, float lo, float hi) { return v < lo ? lo : (v > hi ? hi : v); }
SB_INLINE float3 sbNormalize(float3 a) { return a * (1.0f / sbLength(a)); }

// A rigid transform (or a 3x4 projection) as 12 floats, row-major: rows (m0 m1 m2 | m3), ... Passed by
// value; the host fills it from Eigen.
typedef struct {
  float m[12];
} SbMat34;

// m * (v, 1)
SB_INLINE float3 sbTransform(SbMat34 a, float3 v) {
  return sbMakeFloat3(a.m[0] * v.x + a.m[1] * v.y + a.m[2] * v.z + a.m[3],
                      a.m[4] * v.x + a.m[5] * v.y + a.m[6] * v.z + a.m[7],
                      a.m[8] * v.x + a.m[9] * v.y + a.m[10] * v.z + a.m[11]);
}

// m * (v, 0): rotation part only
SB_INLINE float3 sbRotate(SbMat34 a, float3 v) {
  return sbMakeFloat3(a.m[0] * v.x + a.m[1] * v.y + a.m[2] * v.z, a.m[4] * v.x + a.m[5] * v.y + a.m[6] * v.z,
                      a.m[8] * v.x + a.m[9] * v.y + a.m[10] * v.z);
}

// Pinhole intrinsics (pixels) of the image a kernel works on.
typedef struct {
  float fx, fy, cx, cy;
} SbCamera;

// Marks an invalid normal (normal.x holds this value; a unit normal never does).
#define SB_INVALID_NORMAL (-2.0f)
