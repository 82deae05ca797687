#pragma once
// Reconstruction-volume hints for a rendered sequence (SequenceInfo::volumeSize / volumeInitialPosition):
// a cube, with axes along the first camera's axes, that holds what the camera sees over the sequence.
// Estimated from a coarse exact render (1/8 resolution) of evenly spaced frames: the seen points and camera
// positions are expressed in the first camera's frame, their 2nd-98th percentile box is padded and the cube
// centred on it. The first camera position as fractions of the cube is volumeInitialPosition.

#include <array>

#include "core/intrinsics.h"
#include "core/trajectory.h"
#include "synth/noise_model.h"
#include "synth/scene.h"

namespace sb::synth {

struct VolumeHintParams {
  int subsample = 8;          // render at 1/subsample resolution
  size_t sampledFrames = 60;  // at most this many frames, evenly spaced
  double lowPercentile = 0.02, highPercentile = 0.98;
  double paddingM = 0.2;      // added on every side, metres
  double roundingM = 0.25;    // cube side rounded up to a multiple of this, metres
  double minSizeM = 4.0, maxSizeM = 8.0;  // metres
  bool holdPath = false;  // the cube also holds every camera position (not only the first one)
};

struct VolumeHints {
  double sizeM = 0.0;                                // cube side, metres
  std::array<double, 3> initialPosition{0.5, 0.5, 0.5};  // first camera position / sizeM, per axis
};

// `trajectory` must not be empty. Only the range limits of `sensor` are used.
VolumeHints estimateVolumeHints(const Scene& scene, const Trajectory& trajectory, const Intrinsics& intrinsics,
                                const SensorModel& sensor, const VolumeHintParams& params = {});

}  // namespace sb::synth
