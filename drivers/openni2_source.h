#pragma once
// A live depth camera through OpenNI2 (PrimeSense / Asus Xtion, Kinect v1 through a driver, Orbbec, ...).
// This header does not include OpenNI.h; openni2_source.cpp is the one file that does.
//
// - Opens the device `uri`, or the first device OpenNI2 finds, and one depth stream in the configured mode
//   (default 640x480 at 30 fps). A 1 mm pixel format is preferred; a mode offered only in 100 um units is
//   taken and converted to millimetres, so frames are always millimetres (SequenceInfo::depthScale = 1000).
// - Mirroring and depth-to-colour registration are switched off (the raw depth geometry KinectFusion needs).
// - Intrinsics: each of fx, fy, cx, cy from the options when given, otherwise from the device's field of
//   view (fx = width / (2 tan(hfov / 2)), cx = width / 2: OpenNI2's own convention).
// - Frame timestamps are the device's, mapped onto CLOCK_MONOTONIC (drivers/device_clock.h); DepthFrame::index
//   counts delivered frames from 0. Gaps in the device's frame numbers are counted as drops.
// - A lost camera (the driver reports a disconnect, or no frame for `frameTimeoutSeconds`): with `reconnect`,
//   next() reopens it with backoff (reconnectMinSeconds, doubling up to reconnectMaxSeconds) and carries on;
//   without, next() throws sb::Error. The explicit `uri`, when given, is the device waited for; otherwise
//   whichever device appears first (USB URIs name the bus address, which changes when a camera is replugged).
// - Errors a user can act on (sb::Error): no device (and which were found), device busy, permission denied
//   (naming the udev rule and the group `video`), unsupported mode (listing the modes the device offers).

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "drivers/frame_source.h"

namespace sb {

struct OpenNI2Options {
  std::string uri;                    // device URI; empty = the first device found
  int width = 640;                    // depth mode, pixels
  int height = 480;                   // depth mode, pixels
  int fps = 30;                       // depth mode, frames per second
  std::optional<float> fx, fy, cx, cy;  // intrinsics, pixels; unset = from the device's field of view
  double frameTimeoutSeconds = 2.0;   // no frame for this long: the camera counts as lost
  bool reconnect = true;              // reopen a lost camera (false: next() throws)
  double reconnectMinSeconds = 0.5;   // first wait before reopening; doubles after every failed attempt
  double reconnectMaxSeconds = 10.0;  // longest wait between attempts
};

enum class CameraState { streaming, lost, stopped };
const char* cameraStateName(CameraState state);  // "streaming", "lost", "stopped"

// Counters and state, safe to read from any thread.
struct CameraStats {
  CameraState state = CameraState::streaming;
  std::string uri;            // of the device currently (or last) open
  std::string mode;           // e.g. "640x480@30 1mm" or "160x120@30 100um->1mm"
  uint64_t frames = 0;        // delivered by next()
  uint64_t drops = 0;         // frames the device numbered but never delivered (gaps in its frame index)
  uint64_t disconnects = 0;   // times the camera was lost
  uint64_t reconnects = 0;    // times it was reopened after a loss
  uint64_t attempts = 0;      // failed reopening attempts since the last loss
  std::string lastError;      // why the camera was lost, or why the last attempt failed; empty when streaming
};

class OpenNI2Source : public FrameSource {
 public:
  // Initialises OpenNI2, opens the device and starts the depth stream. Throws sb::Error (see above).
  explicit OpenNI2Source(const OpenNI2Options& options);
  ~OpenNI2Source() override;
  OpenNI2Source(const OpenNI2Source&) = delete;
  OpenNI2Source& operator=(const OpenNI2Source&) = delete;

  const SequenceInfo& info() const override;
  // Blocks until the next frame; nullopt once stop() was called. Throws sb::Error when the camera is lost
  // and `reconnect` is off, or when it sends a frame of another size than the mode.
  std::optional<DepthFrame> next() override;
  // Makes a blocked or later next() return nullopt within about 0.1 s. Thread-safe and async-signal-safe
  // (it only sets a flag), so a SIGINT handler may call it.
  void stop() { stopRequested_.store(true); }
  CameraStats stats() const;

  struct Impl;  // the OpenNI2 side (openni2_source.cpp)

 private:
  std::unique_ptr<Impl> impl_;
  std::atomic<bool> stopRequested_{false};
};

}  // namespace sb
