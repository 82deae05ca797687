#pragma once
// What the drive odometry tests share: a base without any error, so that a test sees only what it sets.

#include "synth/drive_odometry.h"

namespace sb::synth::test {

inline OdometryErrors exactOdometry() {
  OdometryErrors e;
  e.scale = e.yawScale = e.yawBiasDegps = e.noiseMPerSqrtM = e.yawNoiseDegPerSqrtS = 0.0;
  return e;
}

}  // namespace sb::synth::test
