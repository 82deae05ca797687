#include "daemon/openni2_capture.h"

namespace sb::daemon {

namespace {

OpenNI2Options cameraOptions(const SourceConfig& s) {
  if (!s.path.empty())
    throw ConfigError(
        "source.path = \"" + s.path +
        "\" is for replay; an OpenNI2 camera is chosen by source.camera.uri (empty: the first found)");
  if (s.depthScale != 0.0)
    throw ConfigError(
        "source.depth_scale is for replay; an OpenNI2 camera delivers millimetres (leave it 0)");
  const CameraConfig& c = s.camera;
  OpenNI2Options o;
  o.uri = c.uri;
  o.width = c.width;
  o.height = c.height;
  o.fps = c.fps;
  if (c.fx > 0) o.fx = static_cast<float>(c.fx);
  if (c.fy > 0) o.fy = static_cast<float>(c.fy);
  if (c.cx > 0) o.cx = static_cast<float>(c.cx);
  if (c.cy > 0) o.cy = static_cast<float>(c.cy);
  o.frameTimeoutSeconds = c.frameTimeoutSeconds;
  o.reconnect = true;
  o.reconnectMinSeconds = c.reconnectMinSeconds;
  o.reconnectMaxSeconds = c.reconnectMaxSeconds;
  return o;
}

}  // namespace

OpenNI2Capture::OpenNI2Capture(const SourceConfig& config)
    : camera_(std::make_unique<OpenNI2Source>(cameraOptions(config))) {}

std::optional<CapturedFrame> OpenNI2Capture::next() {
  std::optional<DepthFrame> f = camera_->next();
  if (!f) return std::nullopt;
  // After a reconnect the reconstruction goes on: tracking decides whether the camera moved too far
  // meanwhile.
  return CapturedFrame{std::move(*f), false};
}

nlohmann::json OpenNI2Capture::status() const {
  const CameraStats s = camera_->stats();
  nlohmann::json j = {{"type", "openni2"},
                      {"path", s.uri},
                      {"format", "openni2"},
                      {"live", true},
                      {"state", cameraStateName(s.state)},
                      {"mode", s.mode},
                      {"frames", s.frames},
                      {"device_drops", s.drops},
                      {"disconnects", s.disconnects},
                      {"reconnects", s.reconnects}};
  if (s.state == CameraState::lost) j["reconnect_attempts"] = s.attempts;
  if (!s.lastError.empty()) j["source_error"] = s.lastError;
  return j;
}

}  // namespace sb::daemon
