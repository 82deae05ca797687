#pragma once
// A live OpenNI2 camera as the daemon's source (source.type "openni2", settings in source.camera). Frames
// are never waited for: the capture thread reads them as the camera sends them, and the frame queue keeps the
// newest. A lost camera is reopened with backoff while the daemon keeps serving the socket; STATUS shows the
// source's state ("streaming", "lost", "stopped"), device drops, disconnects and reconnects.

#include <memory>

#include "daemon/capture_source.h"
#include "daemon/daemon_config.h"
#include "drivers/openni2_source.h"

namespace sb::daemon {

class OpenNI2Capture : public CaptureSource {
 public:
  // Opens the camera at once (no device, busy, permission, unsupported mode: sb::Error; keys that make no
  // sense for a camera: ConfigError).
  explicit OpenNI2Capture(const SourceConfig& config);

  const SequenceInfo& info() const override { return camera_->info(); }
  bool live() const override { return true; }
  std::optional<CapturedFrame> next() override;
  void stop() override { camera_->stop(); }
  nlohmann::json status() const override;

 private:
  std::unique_ptr<OpenNI2Source> camera_;
};

}  // namespace sb::daemon
