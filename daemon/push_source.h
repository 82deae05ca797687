#pragma once
// Depth frames pushed by a local client (slambooster_ros forwarding a ROS depth topic, or any program using
// client/frame_pusher.h) as the daemon's source: source.type "push", source.path the socket it listens on.
// A live source: the SLAM thread's queue keeps the newest frames and counts drops. One client at a time; when
// it goes away the source waits for the next (a restarted forwarder resumes the stream). The socket has the
// control socket's mode (socket.mode) and the daemon's user and group; any peer that can open it may push.
//
// The pipeline is sized by the stream's first frame (size and intrinsics, e.g. from ROS CameraInfo), so the
// constructor waits for it; SIGTERM/SIGINT while waiting end the wait with an error, whatever the client
// does. A frame outside the bounds every camera door shares (drivers/camera_bounds.h, with
// source.max_frame_pixels), of another size, intrinsics or depth scale than the first, or whose stamp does
// not increase (drivers/stamp_gate.h) is refused (counted, logged) and the stream goes on. A client silent
// for source.push_timeout_s, within a frame or between two, is named in the log and closed; the source waits
// for the next. A connection whose client had already closed before it was accepted is dropped unread (its
// frames are stale).

#include <atomic>
#include <mutex>
#include <optional>
#include <string>

#include "core/unique_fd.h"
#include "daemon/capture_source.h"
#include "daemon/daemon_config.h"
#include "daemon/unix_socket.h"
#include "drivers/pushed_frame.h"
#include "drivers/stamp_gate.h"

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
  enum class Read { frame, refused, closed, stopped };
  // Reads one whole frame from the current client (accepting one first if there is none).
  Read readFrame(PushedFrameHeader& header, DepthRaw& depth);
  // Fills `bytes` from the client (`within`: inside a frame, as the log says); ok, or why not (silent:
  // nothing came for source.push_timeout_s).
  enum class Fill { ok, closed, stopped, silent };
  Fill readExactly(uint8_t* data, size_t bytes, bool within);
  bool skip(size_t bytes);  // reads and drops a refused frame's payload
  bool acceptClient(int timeoutMs);
  std::optional<std::string> refusal(const PushedFrameHeader& h) const;  // why a frame is refused
  bool stopRequested() const;

  SourceConfig config_;
  ListeningSocket listener_;
  UniqueFd client_;
  UniqueFd wake_;  // eventfd: stop() makes every wait return
  SequenceInfo info_;
  std::optional<DepthFrame> first_;  // read by the constructor, returned by the first next()
  bool streamStarted_ = false;       // info_ holds the first frame's size and intrinsics
  size_t index_ = 0;
  std::string peer_;                 // the current client: "pid N (program), uid U"
  StampGate stamps_;

  std::atomic<bool> stopped_{false};
  std::atomic<uint64_t> frames_{0};
  std::atomic<uint64_t> rejected_{0};
  std::atomic<uint64_t> connections_{0};
  std::atomic<bool> connected_{false};
  std::atomic<bool> silent_{false};  // the client has sent nothing for source.push_timeout_s (being closed)
  std::atomic<double> lastAgeMs_{0.0};  // wall clock now - frame timestamp on arrival (see status())
};

}  // namespace sb::daemon
