#include "daemon/pattern_source.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sb::daemon {

namespace {

constexpr double kDepthScale = 1000.0;  // raw units per metre (millimetres)
constexpr double kFocalPerWidth = 0.8;  // fx = fy = 0.8 x width: a 64-degree horizontal field of view
// The room around the camera (metres, camera axes: x right, y down, z forward): the first plane each ray
// meets is the depth. Side walls, floor and ceiling at different distances keep every motion constrained.
constexpr double kLeftWallX = -1.5, kRightWallX = 1.8, kCeilingY = -1.3, kFloorY = 1.0, kBackWallZ = 3.0;

// Distance along the optical axis to the first wall the ray (x, y, 1) meets.
double roomDepth(double x, double y) {
  double z = kBackWallZ;
  if (x < 0) z = std::min(z, kLeftWallX / x);
  if (x > 0) z = std::min(z, kRightWallX / x);
  if (y < 0) z = std::min(z, kCeilingY / y);
  if (y > 0) z = std::min(z, kFloorY / y);
  return z;
}

}  // namespace

PatternSource::PatternSource(const SourceConfig& config)
    : config_(config), fast_(config.pacing == "fast"), start_(std::chrono::steady_clock::now()) {
  const CameraConfig& c = config_.camera;
  info_.path = "pattern";
  info_.format = "pattern";
  info_.intrinsics.width = c.width;
  info_.intrinsics.height = c.height;
  info_.intrinsics.fx = info_.intrinsics.fy = static_cast<float>(kFocalPerWidth * c.width);
  info_.intrinsics.cx = 0.5f * static_cast<float>(c.width - 1);
  info_.intrinsics.cy = 0.5f * static_cast<float>(c.height - 1);
  info_.depthScale = kDepthScale;
  info_.frameCount = config_.maxFrames;
  depth_ = DepthRaw(c.width, c.height);
  for (int v = 0; v < c.height; ++v)
    for (int u = 0; u < c.width; ++u) {
      const double z = roomDepth((u - info_.intrinsics.cx) / info_.intrinsics.fx,
                                 (v - info_.intrinsics.cy) / info_.intrinsics.fy);
      depth_(u, v) = static_cast<uint16_t>(std::lround(z * kDepthScale));
    }
}

std::optional<CapturedFrame> PatternSource::next() {
  const uint64_t index = frames_.load();
  if (config_.maxFrames > 0 && index >= config_.maxFrames) return std::nullopt;
  const double period = 1.0 / config_.camera.fps;
  std::unique_lock lock(mutex_);
  if (!fast_) {
    const auto due = start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                  std::chrono::duration<double>(static_cast<double>(index) * period));
    wake_.wait_until(lock, due, [&] { return stopped_; });
  }
  if (stopped_) return std::nullopt;
  lock.unlock();
  CapturedFrame f;
  f.frame.index = static_cast<size_t>(index);
  f.frame.timestamp = static_cast<double>(index) * period;
  f.frame.depth = depth_;
  ++frames_;
  return f;
}

void PatternSource::stop() {
  std::lock_guard lock(mutex_);
  stopped_ = true;
  wake_.notify_all();
}

nlohmann::json PatternSource::status() const {
  bool stopped;
  {
    std::lock_guard lock(mutex_);
    stopped = stopped_;
  }
  const bool ended = config_.maxFrames > 0 && frames_.load() >= config_.maxFrames;
  return {{"type", "pattern"},        {"path", info_.path},
          {"live", live()},           {"state", ended ? "ended" : stopped ? "stopped" : "running"},
          {"pacing", config_.pacing}, {"frames", frames_.load()}};
}

}  // namespace sb::daemon
