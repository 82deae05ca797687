#pragma once
// The client's side of slamboosterd's push source (drivers/pushed_frame.h): connect to its socket and write
// depth frames. Used by slambooster_ros's depth forwarder; any local program may push frames the same way.

#include <string>

#include "core/image.h"
#include "core/unique_fd.h"
#include "drivers/pushed_frame.h"

namespace sb::client {

class FramePusher {
 public:
  // Connects to the push source's socket. Throws sb::Error naming the path and what to check.
  explicit FramePusher(const std::string& socketPath);
  // Writes one frame (header fields width/height are taken from `depth`). Blocks while the socket's buffer is
  // full (the daemon reads every frame as it arrives; the newest-frame-wins rule is applied after that).
  // Throws sb::Error when the daemon has gone away. A connection the daemon closed since the last frame (a
  // pusher silent for source.push_timeout_s is closed) is made again first.
  void push(PushedFrameHeader header, const DepthRaw& depth);

 private:
  void writeAll(const uint8_t* data, size_t bytes);
  bool closedByDaemon() const;  // the daemon's end of the connection is closed

  std::string path_;
  UniqueFd fd_;
};

}  // namespace sb::client
