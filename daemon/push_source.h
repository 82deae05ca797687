#pragma once
// Depth frames pushed by a local client (slambooster_ros forwarding a ROS depth topic, or any program using
// client/frame_pusher.h) as the daemon's source: source.type "push", source.path the socket it listens on.
// A live source: the SLAM thread's queue keeps the newest frames and counts drops. One client at a time; when
// it goes away the source waits for the next (a restarted forwarder resumes the stream).
//
// The pipeline is sized by the stream's first frame (size and intrinsics, e.g. from ROS CameraInfo), so the
// constructor waits for it; SIGTERM/SIGINT while waiting end the wait with an error. Later frames of another
// size, intrinsics or depth scale are rejected (counted, logged) and the stream goes on.

#include <atomic>
#include <mutex>
#include <optional>
#include <string>

#include "core/unique_fd.h"
#include "daemon/capture_source.h"
#include "daemon/daemon_config.h"
#include "daemon/unix_socket.h"
#include "drivers/pushed_frame.h"

namespace sb::daemon {

class PushSource : public CaptureSource {
 public:
  explicit PushSource(const SourceConfig& config);

  const SequenceInfo& info() const override { return info_; }
  bool live() const override { return true; }
  std::optional<CapturedFrame> next() override;
  void stop() override;
  nlohmann::json status() const override;

 private:
  enum class Read { frame, closed, stopped };
  // Reads one whole frame from the current client (accepting one first if there is none).
  Read readFrame(PushedFrameHeader& header, DepthRaw& depth);
  // Fills `bytes` from the client; false when the client closed or stop() was called.
  bool readExactly(uint8_t* data, size_t bytes);
  bool acceptClient(int timeoutMs);
  bool matchesStream(const PushedFrameHeader& h) const;

  SourceConfig config_;
  ListeningSocket listener_;
  UniqueFd client_;
  UniqueFd wake_;  // eventfd: stop() makes every wait return
  SequenceInfo info_;
  std::optional<DepthFrame> first_;  // read by the constructor, returned by the first next()
  size_t index_ = 0;

  std::atomic<bool> stopped_{false};
  std::atomic<uint64_t> frames_{0};
  std::atomic<uint64_t> rejected_{0};
  std::atomic<uint64_t> connections_{0};
  std::atomic<bool> connected_{false};
  std::atomic<double> lastAgeMs_{0.0};  // wall clock now - frame timestamp on arrival (see status())
};

}  // namespace sb::daemon
