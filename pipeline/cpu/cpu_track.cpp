#include "pipeline/cpu/cpu_track.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "kernels/track.h"
#include "pipeline/cpu/simd4.h"

namespace sb {

namespace {

// The four-lane layer (simd4.h). Lane results equal the scalar kernel's (kernels/track.h) bit for bit,
// on NEON too: NEON flushes denormals, and none arise here from camera-space vertices and unit normals
// (tests/pipeline/cpu/test_cpu_track.cpp checks the bits against the scalar kernel on every target). This
// hand-vectorised version of kernels/track.h's sbTrackPixel stays for speed: the compiler does not vectorise
// the scalar kernel's gathers and branches.
using namespace simd4;  // NOLINT: the lane layer is this file's vocabulary

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
  I4 inliers = splatInt(0), tooFar = splatInt(0), badNormal = splatInt(0), noCorrespondence = splatInt(0);
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

void reduceBandBlocks(const TrackBand& band, int width, int block, TrackSums& sums) {
  float partial[SB_REDUCE_SIZE] = {};
  float row[SB_TRACK_STRIDE];
  const size_t stride = static_cast<size_t>(band.stride);
  for (int r0 = 0; r0 < band.rows; r0 += block) {
    const int r1 = std::min(r0 + block, band.rows);
    for (int x0 = 0; x0 < width; x0 += block) {
      const int x1 = std::min(x0 + block, width);
      float jSum[6] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
      float count = 0.0f;
      for (int r = r0; r < r1; ++r) {
        const float* j = band.values.data() + (static_cast<size_t>(r) * TrackBand::kTrackTerms + 1) * stride;
        for (int x = x0; x < x1; ++x) {
          // J of a pixel that is no inlier is 0; an inlier's translational part is its unit reference normal.
          if (j[x] == 0.0f && j[stride + x] == 0.0f && j[2 * stride + x] == 0.0f) continue;
          count += 1.0f;
          for (int i = 0; i < 6; ++i) jSum[i] += j[i * stride + x];
        }
      }
      blockRow(row, jSum, count);
      reduce(partial, row, 0);
    }
  }
  for (int i = 0; i < SB_REDUCE_SIZE; ++i) sums[i] += partial[i];
}

}  // namespace sb
