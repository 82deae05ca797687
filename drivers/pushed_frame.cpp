#include "drivers/pushed_frame.h"

#include <cmath>
#include <cstring>
#include <string>

#include "core/error.h"
#include "core/image.h"

namespace sb {

namespace {

constexpr char kMagic[4] = {'S', 'B', 'P', 'F'};

template <typename T>
void put(uint8_t*& p, T v) {
  std::memcpy(p, &v, sizeof v);
  p += sizeof v;
}

template <typename T>
T get(const uint8_t*& p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  p += sizeof v;
  return v;
}

}  // namespace

std::array<uint8_t, kPushedHeaderBytes> encodePushedHeader(const PushedFrameHeader& h) {
  std::array<uint8_t, kPushedHeaderBytes> out{};
  uint8_t* p = out.data();
  std::memcpy(p, kMagic, sizeof kMagic);
  p += sizeof kMagic;
  put(p, kPushedFrameVersion);
  put(p, h.width);
  put(p, h.height);
  put(p, h.timestamp);
  put(p, h.depthScale);
  for (float v : {h.fx, h.fy, h.cx, h.cy}) put(p, v);
  return out;
}

PushedFrameHeader decodePushedHeader(const uint8_t* bytes) {
  if (std::memcmp(bytes, kMagic, sizeof kMagic) != 0)
    throw Error("not a pushed depth frame (bad magic): is the client speaking the push source's format?");
  const uint8_t* p = bytes + sizeof kMagic;
  const auto version = get<uint32_t>(p);
  if (version != kPushedFrameVersion)
    throw Error("pushed frame version " + std::to_string(version) + ", expected " +
                std::to_string(kPushedFrameVersion) + ": install matching slambooster and slambooster-ros");
  PushedFrameHeader h;
  h.width = get<uint32_t>(p);
  h.height = get<uint32_t>(p);
  h.timestamp = get<double>(p);
  h.depthScale = get<double>(p);
  h.fx = get<float>(p);
  h.fy = get<float>(p);
  h.cx = get<float>(p);
  h.cy = get<float>(p);
  const auto maxSide = static_cast<uint32_t>(kMaxDepthImageSide);
  if (h.width == 0 || h.height == 0 || h.width > maxSide || h.height > maxSide)
    throw Error("pushed frame size " + std::to_string(h.width) + "x" + std::to_string(h.height) + " is outside 1.." +
                std::to_string(kMaxDepthImageSide) + " pixels per side");
  if (!(h.depthScale > 0) || !std::isfinite(h.depthScale))
    throw Error("pushed frame depth scale " + std::to_string(h.depthScale) + " must be > 0 raw units per metre");
  if (!(h.fx > 0) || !(h.fy > 0) || !std::isfinite(h.cx) || !std::isfinite(h.cy) || !std::isfinite(h.timestamp))
    throw Error("pushed frame intrinsics or timestamp are not valid numbers (fx, fy > 0)");
  return h;
}

size_t pushedPayloadBytes(const PushedFrameHeader& h) {
  return static_cast<size_t>(h.width) * h.height * sizeof(uint16_t);
}

}  // namespace sb
