#pragma once
// The wire format of depth frames pushed into slamboosterd's push source (source.type "push",
// daemon/push_source.h) over a Unix stream socket by a local client (slambooster_ros's depth forwarder,
// client/frame_pusher.h). Both ends are on one machine: numbers are in host byte order. Each frame is a
// fixed-size header followed by width * height uint16 depth values in raw units (row-major, 0 = no reading).

#include <array>
#include <cstddef>
#include <cstdint>

namespace sb {

struct PushedFrameHeader {
  uint32_t width = 0, height = 0;  // pixels
  double timestamp = 0.0;          // seconds: the frame's capture time (a ROS header stamp)
  double depthScale = 0.0;         // raw units per metre
  float fx = 0, fy = 0, cx = 0, cy = 0;  // intrinsics, pixels
};

inline constexpr uint32_t kPushedFrameVersion = 1;
inline constexpr size_t kPushedHeaderBytes = 48;  // magic, version, then the fields above in order

std::array<uint8_t, kPushedHeaderBytes> encodePushedHeader(const PushedFrameHeader& header);
// Throws sb::Error saying what is wrong (not a pushed frame, another version, a size out of range, a
// non-positive scale or focal length).
PushedFrameHeader decodePushedHeader(const uint8_t* bytes);
// Bytes of the depth payload that follows `header`.
size_t pushedPayloadBytes(const PushedFrameHeader& header);

}  // namespace sb
