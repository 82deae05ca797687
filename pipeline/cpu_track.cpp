#include "pipeline/cpu_track.h"

#include <cmath>
#include <cstdint>
#include <cstring>

#include "kernels/track.h"

#include "pipeline/neon_f4.h"

namespace sb {

namespace {

// Four float lanes and their masks. GCC's generic vectors give SSE2 on x86-64, but on armhf GCC splits
// their float arithmetic into scalar VFP code (it keeps NEON, which flushes denormals, for -ffast-math), so
// armhf takes the NEON intrinsics. Every operation is one rounded operation per lane, never contracted: lane
// results equal the scalar kernel's (on NEON up to denormals).
#if defined(__ARM_NEON)
using neon4::F4;
using neon4::splat;
struct M4 {
  uint32x4_t v;  // all ones (true) or zero per lane
};
using I4 = int32x4_t;
inline F4 load(const float* p) { return {vld1q_f32(p)}; }
inline void store(float* p, F4 a) { vst1q_f32(p, a.v); }
inline M4 operator<(F4 a, F4 b) { return {vcltq_f32(a.v, b.v)}; }
inline M4 operator>(F4 a, F4 b) { return {vcgtq_f32(a.v, b.v)}; }
inline M4 operator>=(F4 a, F4 b) { return {vcgeq_f32(a.v, b.v)}; }
inline M4 operator!=(F4 a, F4 b) { return {vmvnq_u32(vceqq_f32(a.v, b.v))}; }
inline M4 operator&(M4 a, M4 b) { return {vandq_u32(a.v, b.v)}; }
inline M4 andNot(M4 a, M4 b) { return {vbicq_u32(a.v, b.v)}; }  // a and not b
inline F4 keep(M4 m, F4 a) { return {vreinterpretq_f32_u32(vandq_u32(vreinterpretq_u32_f32(a.v), m.v))}; }
inline bool any(M4 m) {
  const uint32x2_t halves = vorr_u32(vget_low_u32(m.v), vget_high_u32(m.v));
  return (vget_lane_u32(halves, 0) | vget_lane_u32(halves, 1)) != 0;
}
inline I4 zeroCount() { return vdupq_n_s32(0); }
inline I4 count(I4 c, M4 m) { return vsubq_s32(c, vreinterpretq_s32_u32(m.v)); }  // true lanes are -1
inline int laneSum(I4 c) {
  return vgetq_lane_s32(c, 0) + vgetq_lane_s32(c, 1) + vgetq_lane_s32(c, 2) + vgetq_lane_s32(c, 3);
}
// Pixel indices v * w + u of in-bounds lanes (u, v >= 0, integral floats), 0 elsewhere.
inline void pixelIndices(M4 m, F4 u, F4 v, int w, int32_t out[4]) {
  const int32x4_t iu = vcvtq_s32_f32(keep(m, u).v), iv = vcvtq_s32_f32(keep(m, v).v);
  vst1q_s32(out, vaddq_s32(vmulq_n_s32(iv, w), iu));
}
// Four float3 (12 floats) as x, y and z lanes.
inline void load3(const float* p, F4& x, F4& y, F4& z) {
  const float32x4x3_t t = vld3q_f32(p);
  x = {t.val[0]};
  y = {t.val[1]};
  z = {t.val[2]};
}
// The float3 at four indices as x, y and z lanes.
inline void gather3(const float* p, const int32_t index[4], F4& x, F4& y, F4& z) {
  float32x4x3_t t = {{vdupq_n_f32(0.0f), vdupq_n_f32(0.0f), vdupq_n_f32(0.0f)}};
  t = vld3q_lane_f32(p + 3 * index[0], t, 0);
  t = vld3q_lane_f32(p + 3 * index[1], t, 1);
  t = vld3q_lane_f32(p + 3 * index[2], t, 2);
  t = vld3q_lane_f32(p + 3 * index[3], t, 3);
  x = {t.val[0]};
  y = {t.val[1]};
  z = {t.val[2]};
}
#else
typedef float VF __attribute__((vector_size(16)));
typedef int32_t VI __attribute__((vector_size(16)));
struct F4 {
  VF v;
};
struct M4 {
  VI v;  // -1 (true) or 0 per lane
};
using I4 = VI;
inline F4 splat(float s) { return {VF{s, s, s, s}}; }
inline F4 load(const float* p) {
  VF v;
  std::memcpy(&v, p, sizeof v);
  return {v};
}
inline void store(float* p, F4 a) { std::memcpy(p, &a.v, sizeof a.v); }
inline F4 operator+(F4 a, F4 b) { return {a.v + b.v}; }
inline F4 operator-(F4 a, F4 b) { return {a.v - b.v}; }
inline F4 operator*(F4 a, F4 b) { return {a.v * b.v}; }
inline F4 operator/(F4 a, F4 b) { return {a.v / b.v}; }
inline M4 operator<(F4 a, F4 b) { return {a.v < b.v}; }
inline M4 operator>(F4 a, F4 b) { return {a.v > b.v}; }
inline M4 operator>=(F4 a, F4 b) { return {a.v >= b.v}; }
inline M4 operator!=(F4 a, F4 b) { return {a.v != b.v}; }
inline M4 operator&(M4 a, M4 b) { return {a.v & b.v}; }
inline M4 andNot(M4 a, M4 b) { return {a.v & ~b.v}; }
inline F4 keep(M4 m, F4 a) { return {reinterpret_cast<VF>(reinterpret_cast<VI>(a.v) & m.v)}; }
inline bool any(M4 m) {
  uint64_t halves[2];
  std::memcpy(halves, &m.v, sizeof halves);
  return (halves[0] | halves[1]) != 0;
}
inline I4 zeroCount() { return VI{0, 0, 0, 0}; }
inline I4 count(I4 c, M4 m) { return c - m.v; }
inline int laneSum(I4 c) { return c[0] + c[1] + c[2] + c[3]; }
inline void pixelIndices(M4 m, F4 u, F4 v, int w, int32_t out[4]) {
  const VI iu = __builtin_convertvector(keep(m, u).v, VI), iv = __builtin_convertvector(keep(m, v).v, VI);
  const VI index = iv * w + iu;
  std::memcpy(out, &index, sizeof index);
}
inline void load3(const float* p, F4& x, F4& y, F4& z) {
  x = {VF{p[0], p[3], p[6], p[9]}};
  y = {VF{p[1], p[4], p[7], p[10]}};
  z = {VF{p[2], p[5], p[8], p[11]}};
}
inline void gather3(const float* p, const int32_t index[4], F4& x, F4& y, F4& z) {
  const float *a = p + 3 * index[0], *b = p + 3 * index[1], *c = p + 3 * index[2], *d = p + 3 * index[3];
  x = {VF{a[0], b[0], c[0], d[0]}};
  y = {VF{a[1], b[1], c[1], d[1]}};
  z = {VF{a[2], b[2], c[2], d[2]}};
}
#endif

struct Mat4 {
  F4 m[12];
  explicit Mat4(const SbMat34& a) {
    for (int i = 0; i < 12; ++i) m[i] = splat(a.m[i]);
  }
};

// kernels/common.h's sbTransform / sbRotate, same order of operations.
inline void transform(const Mat4& a, F4 x, F4 y, F4 z, F4& ox, F4& oy, F4& oz) {
  ox = a.m[0] * x + a.m[1] * y + a.m[2] * z + a.m[3];
  oy = a.m[4] * x + a.m[5] * y + a.m[6] * z + a.m[7];
  oz = a.m[8] * x + a.m[9] * y + a.m[10] * z + a.m[11];
}
inline void rotate(const Mat4& a, F4 x, F4 y, F4 z, F4& ox, F4& oy, F4& oz) {
  ox = a.m[0] * x + a.m[1] * y + a.m[2] * z;
  oy = a.m[4] * x + a.m[5] * y + a.m[6] * z;
  oz = a.m[8] * x + a.m[9] * y + a.m[10] * z;
}

struct Counts {
  I4 inliers = zeroCount(), tooFar = zeroCount(), badNormal = zeroCount(), noCorrespondence = zeroCount();
};

// The per-call constants of track().
struct TrackConstants {
  Mat4 toWorld, toReference;
  F4 invalid, zero, half, refWidth, refHeight, squaredDistance, normalThreshold;
  explicit TrackConstants(const TrackInputs& in)
      : toWorld(in.cameraToWorld),
        toReference(in.worldToRefPixel),
        invalid(splat(SB_INVALID_NORMAL)),
        zero(splat(0.0f)),
        half(splat(0.5f)),
        refWidth(splat(static_cast<float>(in.refWidth))),
        refHeight(splat(static_cast<float>(in.refHeight))),
        squaredDistance(splat(squaredDistanceLimit(in.distanceThreshold))),
        normalThreshold(splat(in.normalThreshold)) {}
};

// track() for the four pixels whose vertices and normals start at v and n; writes lane i of the 7 terms to
// out[k * stride + i].
inline void trackQuad(const TrackInputs& in, const TrackConstants& c, const float* v, const float* n,
                      float* out, int stride, Counts& counts) {
  F4 nx, ny, nz;
  load3(n, nx, ny, nz);
  const M4 valid = nx != c.invalid;  // else SB_TRACK_NO_INPUT (not counted)
  if (any(valid)) {
    F4 vx, vy, vz, px, py, pz, hx, hy, hz;
    load3(v, vx, vy, vz);
    transform(c.toWorld, vx, vy, vz, px, py, pz);
    transform(c.toReference, px, py, pz, hx, hy, hz);
    // u = floor(q) is in [0, refWidth - 1] exactly when q is in [0, refWidth); there floor = truncation.
    const F4 qx = hx / hz + c.half, qy = hy / hz + c.half;
    const M4 inside =
        valid & (hz > c.zero) & (qx >= c.zero) & (qy >= c.zero) & (qx < c.refWidth) & (qy < c.refHeight);
    counts.noCorrespondence = count(counts.noCorrespondence, andNot(valid, inside));
    if (any(inside)) {
      int32_t index[4];
      pixelIndices(inside, qx, qy, in.refWidth, index);
      F4 rnx, rny, rnz, rvx, rvy, rvz;
      gather3(in.refNormal, index, rnx, rny, rnz);
      gather3(in.refVertex, index, rvx, rvy, rvz);
      const M4 referenced = inside & (rnx != c.invalid);
      const F4 dx = rvx - px, dy = rvy - py, dz = rvz - pz;
      const M4 near = andNot(referenced, dx * dx + dy * dy + dz * dz > c.squaredDistance);
      F4 pnx, pny, pnz;
      rotate(c.toWorld, nx, ny, nz, pnx, pny, pnz);
      const M4 inlier = andNot(near, pnx * rnx + pny * rny + pnz * rnz < c.normalThreshold);
      counts.noCorrespondence = count(counts.noCorrespondence, andNot(inside, referenced));
      counts.tooFar = count(counts.tooFar, andNot(referenced, near));
      counts.badNormal = count(counts.badNormal, andNot(near, inlier));
      counts.inliers = count(counts.inliers, inlier);
      store(out, keep(inlier, rnx * dx + rny * dy + rnz * dz));
      store(out + stride, keep(inlier, rnx));
      store(out + 2 * stride, keep(inlier, rny));
      store(out + 3 * stride, keep(inlier, rnz));
      store(out + 4 * stride, keep(inlier, py * rnz - pz * rny));  // sbCross(p, rn)
      store(out + 5 * stride, keep(inlier, pz * rnx - px * rnz));
      store(out + 6 * stride, keep(inlier, px * rny - py * rnx));
      return;
    }
  }
  for (int k = 0; k < TrackBand::kTrackTerms; ++k) store(out + k * stride, c.zero);
}

// Sums row a_I * a_J over J = I..6 of the 7 arrays of one row into sums[first + J - I] (the upper triangle
// of the 7x7 products, row I), each in four float lanes.
template <int I>
void reduceProducts(const float* row, int stride, TrackSums& sums) {
  constexpr int kCount = TrackBand::kTrackTerms - I;
  constexpr int kFirst = I * TrackBand::kTrackTerms - I * (I - 1) / 2;
  F4 acc[kCount];
  for (F4& a : acc) a = splat(0.0f);
  const float* ai = row + I * stride;
  for (int x = 0; x < stride; x += 4) {
    const F4 a = load(ai + x);
#pragma GCC unroll 7
    for (int j = 0; j < kCount; ++j) acc[j] = acc[j] + a * load(ai + j * stride + x);
  }
  for (int j = 0; j < kCount; ++j) {
    float lanes[4];
    store(lanes, acc[j]);
    const double lane01 = static_cast<double>(lanes[0]) + lanes[1];
    const double lane23 = static_cast<double>(lanes[2]) + lanes[3];
    sums[kFirst + j] += lane01 + lane23;
  }
}

}  // namespace

float squaredDistanceLimit(float distance) {
  if (std::isnan(distance)) return INFINITY;  // sqrtf(s) > NaN never holds
  if (distance < 0.0f) return -1.0f;          // always holds
  if (distance == INFINITY) return INFINITY;
  float s = distance * distance;
  while (s > 0.0f && std::sqrt(s) > distance) s = std::nextafter(s, 0.0f);
  while (std::sqrt(std::nextafter(s, INFINITY)) <= distance) s = std::nextafter(s, INFINITY);
  return s;
}

void trackBand(const TrackInputs& in, int y0, int y1, TrackBand& band) {
  const int w = in.width;
  band.rows = y1 - y0;
  band.stride = (w + 3) / 4 * 4;
  band.values.resize(static_cast<size_t>(band.rows) * TrackBand::kTrackTerms * band.stride);
  const TrackConstants c(in);
  Counts counts;
  const int full = w / 4 * 4;
  for (int y = y0; y < y1; ++y) {
    float* out = band.values.data() + static_cast<size_t>(y - y0) * TrackBand::kTrackTerms * band.stride;
    const size_t rowStart = 3 * static_cast<size_t>(y) * w;
    const float* v = in.vertex + rowStart;
    const float* n = in.normal + rowStart;
    for (int x = 0; x < full; x += 4) trackQuad(in, c, v + 3 * x, n + 3 * x, out + x, band.stride, counts);
    if (full < w) {  // the last pixels, padded with pixels without input
      float tailV[12] = {}, tailN[12] = {};
      for (int i = 0; i < 4; ++i) tailN[3 * i] = SB_INVALID_NORMAL;
      std::memcpy(tailV, v + 3 * full, 3 * sizeof(float) * (w - full));
      std::memcpy(tailN, n + 3 * full, 3 * sizeof(float) * (w - full));
      trackQuad(in, c, tailV, tailN, out + full, band.stride, counts);
    }
  }
  band.inliers = laneSum(counts.inliers);
  band.tooFar = laneSum(counts.tooFar);
  band.badNormal = laneSum(counts.badNormal);
  band.noCorrespondence = laneSum(counts.noCorrespondence);
}

void reduceBand(const TrackBand& band, TrackSums& sums) {
  for (int r = 0; r < band.rows; ++r) {
    const float* row = band.values.data() + static_cast<size_t>(r) * TrackBand::kTrackTerms * band.stride;
    reduceProducts<0>(row, band.stride, sums);
    reduceProducts<1>(row, band.stride, sums);
    reduceProducts<2>(row, band.stride, sums);
    reduceProducts<3>(row, band.stride, sums);
    reduceProducts<4>(row, band.stride, sums);
    reduceProducts<5>(row, band.stride, sums);
    reduceProducts<6>(row, band.stride, sums);
  }
  sums[28] += band.inliers;
  sums[29] += band.tooFar;
  sums[30] += band.badNormal;
  sums[31] += band.noCorrespondence;
}

}  // namespace sb
