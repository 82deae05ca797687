#include "synth/synth_sequence.h"

#include <algorithm>
#include <array>
#include <future>
#include <sstream>

#include "core/error.h"
#include "core/thread_pool.h"
#include "drivers/tum_writer.h"
#include "synth/renderer.h"
#include "synth/scene_generator.h"

namespace sb::synth {

namespace {
constexpr int kFramesPerThreadPerBatch = 4;  // batch size = this x pool threads
}

Intrinsics iclNuimIntrinsics() {
  Intrinsics k;
  k.width = 640;
  k.height = 480;
  k.fx = 481.2f;
  k.fy = 480.f;
  k.cx = 319.5f;
  k.cy = 239.5f;
  return k;
}

SynthResult synthesizeSequence(const Trajectory& trajectory, const SynthOptions& options,
                               const std::function<void(size_t, size_t)>& progress) {
  if (trajectory.empty()) throw Error("synth: the trajectory has no poses; give a TUM file with at least one pose");
  return synthesizeSequence(generateScene(options.scene, options.seed), trajectory, options, progress);
}

SynthResult synthesizeSequence(const Scene& scene, const Trajectory& full, const SynthOptions& options,
                               const std::function<void(size_t, size_t)>& progress) {
  if (full.empty()) throw Error("synth: the trajectory has no poses; give a TUM file with at least one pose");
  Trajectory trajectory = full;
  if (options.maxFrames > 0 && trajectory.size() > options.maxFrames) trajectory.resize(options.maxFrames);

  for (size_t i = 0; i < trajectory.size(); ++i) {
    const Eigen::Vector3f p = trajectory[i].position().cast<float>();
    if (!scene.insideRoom(p)) {
      std::ostringstream msg;
      msg << "synth: camera " << i << " at t=" << trajectory[i].timestamp << " s (position " << p.transpose()
          << " m) is outside the '" << scene.name << "' room (" << scene.roomMin.transpose() << ") - ("
          << scene.roomMax.transpose() << "); the scenes are laid out for the ICL-NUIM living-room trajectories"
          << " and the built-in one";
      throw Error(msg.str());
    }
  }

  SynthResult result;
  result.volume = estimateVolumeHints(scene, trajectory, options.intrinsics, options.sensor, options.volumeHints);
  SequenceInfo info;
  info.path = options.outDir;
  info.format = "synthetic";
  info.intrinsics = options.intrinsics;
  info.depthScale = options.depthScale;
  info.frameCount = trajectory.size();
  info.volumeSize = result.volume.sizeM;
  info.volumeInitialPosition = result.volume.initialPosition;
  TumSequenceWriter writer(options.outDir, info, options.overwrite);
  writer.writeGroundTruth(trajectory);

  const Renderer renderer(scene, options.intrinsics);
  auto covered = [&](size_t i) {
    return std::any_of(options.coveredFrames.begin(), options.coveredFrames.end(),
                       [i](const std::pair<size_t, size_t>& r) { return i >= r.first && i < r.second; });
  };
  ThreadPool& pool = ThreadPool::global();
  const int batch = kFramesPerThreadPerBatch * static_cast<int>(pool.threadCount());
  // Two batches of frames: the pool renders one while a writer thread encodes and writes the other.
  std::array<std::vector<DepthFrame>, 2> frames;
  for (auto& b : frames) b.resize(static_cast<size_t>(batch));
  std::future<void> writing;
  size_t valid = 0;
  const int total = static_cast<int>(trajectory.size());
  for (int first = 0, b = 0; first < total; first += batch, b ^= 1) {
    const int count = std::min(batch, total - first);
    std::vector<DepthFrame>& current = frames[static_cast<size_t>(b)];
    pool.parallelFor(0, count, 1, [&](int, int begin, int end) {
      DepthMeters meters;
      for (int j = begin; j < end; ++j) {
        const size_t index = static_cast<size_t>(first + j);
        DepthFrame& frame = current[static_cast<size_t>(j)];
        frame.index = index;
        frame.timestamp = trajectory[index].timestamp;
        if (covered(index)) {
          frame.depth.resize(options.intrinsics.width, options.intrinsics.height, 0);
          continue;
        }
        renderer.render(trajectory[index].T_camera_to_world, options.sensor, frameSeed(options.seed, index), meters,
                        /*parallel=*/false);
        toRaw(meters, options.depthScale, frame.depth);
      }
    });
    for (int j = 0; j < count; ++j) {
      const auto& px = current[static_cast<size_t>(j)].depth.pixels();
      valid += static_cast<size_t>(std::count_if(px.begin(), px.end(), [](uint16_t v) { return v != 0; }));
    }
    if (writing.valid()) writing.get();  // the previous batch is written (rethrows its error)
    if (progress && first > 0) progress(static_cast<size_t>(first), trajectory.size());
    writing = std::async(std::launch::async, [&writer, &current, count] {
      for (int j = 0; j < count; ++j) writer.write(current[static_cast<size_t>(j)]);
    });
  }
  if (writing.valid()) writing.get();
  if (progress) progress(trajectory.size(), trajectory.size());
  writer.finish();
  result.frames = trajectory.size();
  result.validFraction = static_cast<double>(valid) /
                         (static_cast<double>(result.frames) * options.intrinsics.width * options.intrinsics.height);
  return result;
}

}  // namespace sb::synth
