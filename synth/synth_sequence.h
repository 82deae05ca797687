#pragma once
// Renders a whole synthetic sequence along a trajectory and writes it in TUM layout (depth/*.png, depth.txt,
// groundtruth.txt with the poses used, calibration.json with the volume hints). Frames are rendered in
// parallel batches on ThreadPool::global() and written in order; frame i's noise is seeded with
// frameSeed(seed, i), so the output does not depend on the thread count.

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/intrinsics.h"
#include "core/trajectory.h"
#include "synth/noise_model.h"
#include "synth/scene.h"
#include "synth/volume_hints.h"

namespace sb::synth {

// ICL-NUIM's depth camera: 640x480, fx 481.2, fy 480, principal point at the image centre.
Intrinsics iclNuimIntrinsics();
constexpr double kIclDepthScale = 5000.0;  // raw units per metre (ICL-NUIM / TUM)

struct SynthOptions {
  std::string outDir;
  bool overwrite = false;
  std::string scene = "livingroom";
  uint64_t seed = 0;  // scene layout and noise
  Intrinsics intrinsics = iclNuimIntrinsics();
  double depthScale = kIclDepthScale;
  SensorModel sensor;
  size_t maxFrames = 0;  // 0 = the whole trajectory
  // Frames [begin, end) written with no depth at all (every pixel 0: a covered lens); their poses stay in
  // groundtruth.txt.
  std::vector<std::pair<size_t, size_t>> coveredFrames;
  VolumeHintParams volumeHints;  // how calibration.json's volume hints are estimated
};

struct SynthResult {
  size_t frames = 0;
  double validFraction = 0.0;  // fraction of pixels with a reading, over all frames
  VolumeHints volume;
};

// progress(framesDone, framesTotal) is called after each written batch. Throws sb::Error (empty trajectory,
// camera outside the room, unwritable output, ...).
SynthResult synthesizeSequence(const Trajectory& trajectory, const SynthOptions& options,
                               const std::function<void(size_t, size_t)>& progress = {});
// The same in `scene` (e.g. stressScene's copy of a generated room) instead of generating options.scene;
// options.scene and options.seed still name the sequence and seed its noise.
SynthResult synthesizeSequence(const Scene& scene, const Trajectory& trajectory, const SynthOptions& options,
                               const std::function<void(size_t, size_t)>& progress = {});

}  // namespace sb::synth
