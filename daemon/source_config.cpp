#include "daemon/source_config.h"

#include <algorithm>

#include "daemon/source_registry.h"
#include "drivers/camera_bounds.h"

namespace sb::daemon {

void CameraConfig::read(ConfigReader& r) {
  r.string("uri", uri);
  r.integer("width", width, 1, 8192);
  r.integer("height", height, 1, 8192);
  r.integer("fps", fps, 1, 1000);
  r.number("fx", fx, 0.0, 1e5);
  r.number("fy", fy, 0.0, 1e5);
  r.number("cx", cx, 0.0, 1e5);
  r.number("cy", cy, 0.0, 1e5);
  r.number("frame_timeout_s", frameTimeoutSeconds, 0.05, 3600.0);
  r.number("reconnect_min_s", reconnectMinSeconds, 0.01, 3600.0);
  r.number("reconnect_max_s", reconnectMaxSeconds, 0.01, 3600.0);
  if (reconnectMaxSeconds < reconnectMinSeconds)
    r.fail("reconnect_max_s", "a value >= 'reconnect_min_s' (" + std::to_string(reconnectMinSeconds) + " s)");
}

void SourceConfig::read(ConfigReader& r) {
  r.string("type", type);
  r.string("path", path);
  r.string("pacing", pacing, {"recorded", "fast"});
  r.number("speed", speed, 0.01, 100.0);
  r.string("at_end", atEnd, {"stop", "loop", "exit"});
  r.integer("max_frames", maxFrames, 0, 100000000);
  r.number("depth_scale", depthScale, 0.0, kMaxDepthScale);
  if (depthScale != 0.0 && depthScale < kMinDepthScale)  // 0: from calibration.json / the format
    r.fail("depth_scale", "0 (from the sequence) or " + std::to_string(static_cast<int>(kMinDepthScale)) +
                              " to " + std::to_string(static_cast<int>(kMaxDepthScale)) +
                              " raw units per metre (1000 for millimetres, 5000 for TUM)");
  r.integer("queue_frames", queueFrames, 1, 256);
  r.string("depth_topic", depthTopic);
  r.string("odometry", odometry);
  if (odometry.empty()) r.fail("odometry", "\"auto\", \"socket\", \"none\" or the path of an odometry.txt");
  r.string("odom_topic", odomTopic);
  r.string("camera_mount", cameraMount);
  r.number("push_timeout_s", pushTimeoutSeconds, 0.1, 3600.0);
  r.integer("max_frame_pixels", maxFramePixels, size_t(kMinDepthImageSide) * kMinDepthImageSide,
            size_t(kMaxDepthImageSide) * kMaxDepthImageSide);
  r.section("camera", [&](ConfigReader& section) { camera.read(section); });
  const auto types = sourceTypes();
  if (std::find(types.begin(), types.end(), type) == types.end()) {
    std::string known;
    for (const auto& t : types) known += (known.empty() ? "\"" : ", \"") + t + "\"";
    r.fail("type", "one of " + known);
  }
}

nlohmann::json CameraConfig::toJson() const {
  return {{"uri", uri},
          {"width", width},
          {"height", height},
          {"fps", fps},
          {"fx", fx},
          {"fy", fy},
          {"cx", cx},
          {"cy", cy},
          {"frame_timeout_s", frameTimeoutSeconds},
          {"reconnect_min_s", reconnectMinSeconds},
          {"reconnect_max_s", reconnectMaxSeconds}};
}

nlohmann::json SourceConfig::toJson() const {
  return {{"type", type},
          {"path", path},
          {"pacing", pacing},
          {"speed", speed},
          {"at_end", atEnd},
          {"max_frames", maxFrames},
          {"depth_scale", depthScale},
          {"queue_frames", queueFrames},
          {"depth_topic", depthTopic},
          {"odometry", odometry},
          {"odom_topic", odomTopic},
          {"camera_mount", cameraMount},
          {"push_timeout_s", pushTimeoutSeconds},
          {"max_frame_pixels", maxFramePixels},
          {"camera", camera.toJson()}};
}

}  // namespace sb::daemon
