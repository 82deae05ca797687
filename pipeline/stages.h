#pragma once
// The classic KinectFusion stage names, used identically in the API, the kernels, the tests, the timing
// labels and the log columns.

#include <array>

namespace sb {

enum class Stage {
  mm2meters,
  bilateralFilter,
  halfSampleRobust,
  depth2vertex,
  vertex2normal,
  track,
  reduce,
  integrate,
  raycast,
  render,
};
constexpr int kStageCount = 10;

constexpr const char* stageName(Stage s) {
  constexpr const char* names[kStageCount] = {"mm2meters",     "bilateralFilter", "halfSampleRobust", "depth2vertex",
                                              "vertex2normal", "track",           "reduce",           "integrate",
                                              "raycast",       "render"};
  return names[static_cast<int>(s)];
}

// What integrate and raycast did (issue 43: work in proportion to the surface), summed over a frame's calls.
struct StageWork {
  long long integrateBlocks = 0;   // blocks of 8^3 voxels integrate visited (all its calls of the frame)
  long long carvingIntegrations = 0;  // integrations that also carved free space (visited every block in view)
  long long raycastPixels = 0;     // pixels of the frame's last raycast
  // Steps of that raycast's marches (0: not counted, the opencl backend): tsdf samples (interpolations; the
  // gradient at a hit not counted) and lookups of the empty-space skipping grid.
  long long raycastSamples = 0;
  long long raycastLookups = 0;
};

// Milliseconds spent per stage (host clock), indexed by Stage.
struct StageTimes {
  std::array<double, kStageCount> ms{};
  // Milliseconds per stage measured on the device (OpenCL profiling events: kernel start to end); 0 for the
  // stages of backends without a device clock (cpu).
  std::array<double, kStageCount> deviceMs{};
  StageWork work;  // counts beside the times
  double& operator[](Stage s) { return ms[static_cast<int>(s)]; }
  double operator[](Stage s) const { return ms[static_cast<int>(s)]; }
  // Preprocessing + tracking + integration + raycast: everything except render (the paper's computation time).
  double computationMs() const {
    double sum = 0;
    for (int i = 0; i < kStageCount; ++i)
      if (i != static_cast<int>(Stage::render)) sum += ms[i];
    return sum;
  }
};

}  // namespace sb
