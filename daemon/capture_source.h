#pragma once
// The daemon's frame-source interface: a FrameSource that also knows whether it is live, can be stopped from
// another thread, and reports its state. Implementations: replay_source.h (recorded sequences, source.type
// "replay") and openni2_capture.h (an OpenNI2 depth camera, "openni2"). A new one is one file pair plus one
// entry in source_registry.cpp; its settings, if any, go in SourceConfig (daemon_config.h).

#include <nlohmann/json.hpp>
#include <optional>

#include "drivers/frame_source.h"

namespace sb::daemon {

struct CapturedFrame {
  DepthFrame frame;
  bool restart = false;  // first frame of a new pass (a looping replay started over): a new reconstruction
};

class CaptureSource {
 public:
  virtual ~CaptureSource() = default;
  virtual const SequenceInfo& info() const = 0;
  // Live sources (cameras) do not wait for the SLAM thread: when it is slower, the newest frame wins and
  // the others are dropped and counted. Replays are never dropped.
  virtual bool live() const = 0;
  // Blocks until the next frame is due. nullopt when the source has ended or stop() was called. Throws
  // sb::Error on bad input.
  virtual std::optional<CapturedFrame> next() = 0;
  // Thread-safe: makes a blocked or later next() return nullopt promptly.
  virtual void stop() = 0;
  // STATUS fields: at least "type", "path", "live", "state", "frames".
  virtual nlohmann::json status() const = 0;
};

}  // namespace sb::daemon
