#pragma once
// The four-lane layer (simd4.h) in plain C++: targets with neither SSE2 nor NEON, and SB_SIMD4_PORTABLE.
// Included by simd4.h only.

#include <cstdint>
#include <cstring>

#include "kernels/common.h"

namespace sb {
namespace simd4 {

struct F4 {
  float v[4];
};
struct I4 {
  int32_t v[4];
};
struct M4 {
  int32_t v[4];  // -1 (true) or 0 per lane
};
inline F4 splat(float s) { return {{s, s, s, s}}; }
inline F4 make4(float x, float y, float z, float w) { return {{x, y, z, w}}; }
inline F4 load(const float* p) { return {{p[0], p[1], p[2], p[3]}}; }
inline void store(float* p, F4 a) { std::memcpy(p, a.v, sizeof a.v); }
inline F4 operator+(F4 a, F4 b) {
  return {{a.v[0] + b.v[0], a.v[1] + b.v[1], a.v[2] + b.v[2], a.v[3] + b.v[3]}};
}
inline F4 operator-(F4 a, F4 b) {
  return {{a.v[0] - b.v[0], a.v[1] - b.v[1], a.v[2] - b.v[2], a.v[3] - b.v[3]}};
}
inline F4 operator*(F4 a, F4 b) {
  return {{a.v[0] * b.v[0], a.v[1] * b.v[1], a.v[2] * b.v[2], a.v[3] * b.v[3]}};
}
inline F4 operator/(F4 a, F4 b) {
  return {{a.v[0] / b.v[0], a.v[1] / b.v[1], a.v[2] / b.v[2], a.v[3] / b.v[3]}};
}
template <int i>
inline float lane(F4 a) {
  return a.v[i];
}
template <int i>
inline F4 broadcast(F4 a) {
  return splat(a.v[i]);
}
inline F4 pairSum(F4 a, F4 b) {
  return {{a.v[0] + a.v[1], a.v[2] + a.v[3], b.v[0] + b.v[1], b.v[2] + b.v[3]}};
}
inline F4 pick01(F4 a, F4 b) { return {{a.v[0], a.v[1], b.v[0], b.v[1]}}; }
inline F4 pick23(F4 a, F4 b) { return {{a.v[2], a.v[3], b.v[2], b.v[3]}}; }
inline F4 pick12(F4 a, F4 b) { return {{a.v[1], a.v[2], b.v[1], b.v[2]}}; }
inline F4 weights0(F4 one, F4 f) { return {{one.v[0], f.v[0], one.v[0], f.v[0]}}; }
inline F4 weights1(F4 one, F4 f) { return {{one.v[1], f.v[1], one.v[1], f.v[1]}}; }
inline F4 weights2(F4 one, F4 f) { return {{one.v[2], f.v[2], one.v[2], f.v[2]}}; }
inline bool insideXyz(F4 a, F4 lo, F4 hi) {
  bool inside = true;
  for (int i = 0; i < 3; ++i) inside = inside && a.v[i] >= lo.v[i] && a.v[i] < hi.v[i];
  return inside;
}
inline float min012(F4 a) { return sbFmin(a.v[0], sbFmin(a.v[1], a.v[2])); }
inline F4 tsdf4(const int16_t* p) { return {{float(p[0]), float(p[2]), float(p[4]), float(p[6])}}; }
inline F4 tsdf2x2(const int16_t* a, const int16_t* b) {
  return {{float(a[0]), float(a[2]), float(b[0]), float(b[2])}};
}
inline I4 truncate(F4 a) { return {{int32_t(a.v[0]), int32_t(a.v[1]), int32_t(a.v[2]), int32_t(a.v[3])}}; }
inline F4 toFloat(I4 a) { return {{float(a.v[0]), float(a.v[1]), float(a.v[2]), float(a.v[3])}}; }
inline I4 splatInt(int s) { return {{s, s, s, s}}; }
inline I4 operator+(I4 a, I4 b) {
  return {{a.v[0] + b.v[0], a.v[1] + b.v[1], a.v[2] + b.v[2], a.v[3] + b.v[3]}};
}
inline I4 operator-(I4 a, I4 b) {
  return {{a.v[0] - b.v[0], a.v[1] - b.v[1], a.v[2] - b.v[2], a.v[3] - b.v[3]}};
}
inline I4 operator^(I4 a, I4 b) {
  return {{a.v[0] ^ b.v[0], a.v[1] ^ b.v[1], a.v[2] ^ b.v[2], a.v[3] ^ b.v[3]}};
}
inline I4 operator&(I4 a, I4 b) {
  return {{a.v[0] & b.v[0], a.v[1] & b.v[1], a.v[2] & b.v[2], a.v[3] & b.v[3]}};
}
inline I4 shiftRight(I4 a, int s) { return {{a.v[0] >> s, a.v[1] >> s, a.v[2] >> s, a.v[3] >> s}}; }
inline I4 notGreaterEqualZero(F4 a) {
  return {
      {a.v[0] >= 0.0f ? 0 : -1, a.v[1] >= 0.0f ? 0 : -1, a.v[2] >= 0.0f ? 0 : -1, a.v[3] >= 0.0f ? 0 : -1}};
}
inline F4 keepWhereNonZero(F4 a, F4 test) {
  F4 r = a;
  for (int i = 0; i < 4; ++i) r.v[i] = test.v[i] != 0.0f ? a.v[i] : 0.0f;
  return r;
}
template <int i>
inline int lane(I4 a) {
  return a.v[i];
}
inline M4 operator<(F4 a, F4 b) {
  return {{-(a.v[0] < b.v[0]), -(a.v[1] < b.v[1]), -(a.v[2] < b.v[2]), -(a.v[3] < b.v[3])}};
}
inline M4 operator>(F4 a, F4 b) {
  return {{-(a.v[0] > b.v[0]), -(a.v[1] > b.v[1]), -(a.v[2] > b.v[2]), -(a.v[3] > b.v[3])}};
}
inline M4 operator>=(F4 a, F4 b) {
  return {{-(a.v[0] >= b.v[0]), -(a.v[1] >= b.v[1]), -(a.v[2] >= b.v[2]), -(a.v[3] >= b.v[3])}};
}
inline M4 operator!=(F4 a, F4 b) {
  return {{-(a.v[0] != b.v[0]), -(a.v[1] != b.v[1]), -(a.v[2] != b.v[2]), -(a.v[3] != b.v[3])}};
}
inline M4 operator&(M4 a, M4 b) {
  return {{a.v[0] & b.v[0], a.v[1] & b.v[1], a.v[2] & b.v[2], a.v[3] & b.v[3]}};
}
inline M4 andNot(M4 a, M4 b) {
  return {{a.v[0] & ~b.v[0], a.v[1] & ~b.v[1], a.v[2] & ~b.v[2], a.v[3] & ~b.v[3]}};
}
inline F4 keep(M4 m, F4 a) {  // the bits of a where m, +0 elsewhere
  F4 r;
  for (int i = 0; i < 4; ++i) r.v[i] = m.v[i] ? a.v[i] : 0.0f;
  return r;
}
inline bool any(M4 m) { return (m.v[0] | m.v[1] | m.v[2] | m.v[3]) != 0; }
inline F4 min(F4 a, F4 b) {
  F4 r;
  for (int i = 0; i < 4; ++i) r.v[i] = sbFmin(a.v[i], b.v[i]);
  return r;
}
inline F4 max(F4 a, F4 b) {
  F4 r;
  for (int i = 0; i < 4; ++i) r.v[i] = sbFmax(a.v[i], b.v[i]);
  return r;
}
inline F4 select(M4 m, F4 a, F4 b) {  // m ? a : b
  F4 r;
  for (int i = 0; i < 4; ++i) r.v[i] = m.v[i] ? a.v[i] : b.v[i];
  return r;
}
inline float max012(F4 a) { return sbFmax(a.v[0], sbFmax(a.v[1], a.v[2])); }
inline int bits012(M4 m) { return (m.v[0] & 1) | (m.v[1] & 2) | (m.v[2] & 4); }  // bit i: lane i is true (i < 3)
inline I4 count(I4 c, M4 m) { return {{c.v[0] - m.v[0], c.v[1] - m.v[1], c.v[2] - m.v[2], c.v[3] - m.v[3]}}; }

}  // namespace simd4
}  // namespace sb
