#pragma once
// The NEON core shared by the CPU backend's four-lane layers on armhf (pipeline/cpu_track.cpp,
// pipeline/cpu_raycast_lanes.h): four float lanes and their arithmetic, one rounded IEEE operation per lane.
// GCC's generic vectors would split float arithmetic into scalar VFP code there, hence the intrinsics.
// Each layer adds the masks, loads and conversions it needs; F4's operators are found by argument lookup.

#if defined(__ARM_NEON)
#include <arm_neon.h>

namespace sb {
namespace neon4 {

struct F4 {
  float32x4_t v;
};
inline F4 splat(float s) { return {vdupq_n_f32(s)}; }
inline F4 operator+(F4 a, F4 b) { return {vaddq_f32(a.v, b.v)}; }
inline F4 operator-(F4 a, F4 b) { return {vsubq_f32(a.v, b.v)}; }
inline F4 operator*(F4 a, F4 b) { return {vmulq_f32(a.v, b.v)}; }
inline F4 operator/(F4 a, F4 b) {  // ARMv7 NEON has no division: one VFP division per lane
  float x[4], y[4];
  vst1q_f32(x, a.v);
  vst1q_f32(y, b.v);
  for (int i = 0; i < 4; ++i) x[i] /= y[i];
  return {vld1q_f32(x)};
}

}  // namespace neon4
}  // namespace sb

#endif
