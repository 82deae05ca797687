#include "ros/depth_image.h"

#include <cmath>
#include <cstring>
#include <limits>

#include "core/error.h"

namespace sb::ros_bridge {

namespace {

// The largest raw value that is a reading (65535 means "none" to the pipeline's readers).
constexpr double kMaxRaw = 65534.0;

bool isMillimetres(const std::string& e) { return e == "16UC1" || e == "mono16"; }
bool isMetres(const std::string& e) { return e == "32FC1"; }

uint16_t quantise(double metres, double depthScale) {
  if (!std::isfinite(metres) || !(metres > 0)) return 0;
  const double raw = std::round(metres * depthScale);
  return raw >= 1.0 && raw <= kMaxRaw ? static_cast<uint16_t>(raw) : 0;
}

template <typename T>
T readPixel(const uint8_t* p, bool swap) {
  uint8_t bytes[sizeof(T)];
  std::memcpy(bytes, p, sizeof(T));
  if (swap)
    for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
  T v;
  std::memcpy(&v, bytes, sizeof(T));
  return v;
}

bool hostIsBigEndian() {
  const uint16_t one = 1;
  uint8_t first;
  std::memcpy(&first, &one, 1);
  return first == 0;
}

}  // namespace

bool isDepthEncoding(const std::string& encoding) { return isMillimetres(encoding) || isMetres(encoding); }

double defaultDepthScale(const std::string& encoding) {
  return isMillimetres(encoding) ? kMillimetreScale : kFloatMetresScale;
}

DepthRaw toDepthRaw(const sensor_msgs::Image& image, double depthScale, const std::string& where) {
  if (!isDepthEncoding(image.encoding))
    throw Error(where + ": encoding '" + image.encoding +
                "' is not a depth encoding (16UC1 millimetres or 32FC1 metres): is this the depth topic?");
  const int w = static_cast<int>(image.width), h = static_cast<int>(image.height);
  if (image.width == 0 || image.height == 0 || image.width > kMaxDepthImageSide || image.height > kMaxDepthImageSide)
    throw Error(where + ": image size " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                " is outside 1.." + std::to_string(kMaxDepthImageSide) + " pixels per side");
  const size_t bytesPerPixel = isMetres(image.encoding) ? sizeof(float) : sizeof(uint16_t);
  const size_t rowBytes = static_cast<size_t>(w) * bytesPerPixel;
  if (image.step < rowBytes || image.data.size() / image.step < static_cast<size_t>(h))
    throw Error(where + ": " + std::to_string(image.data.size()) + " data bytes with step " +
                std::to_string(image.step) + " cannot hold " + std::to_string(w) + "x" + std::to_string(h) +
                " pixels of " + image.encoding + " (a damaged message?)");
  const bool swap = (image.is_bigendian != 0) != hostIsBigEndian();
  const bool exactMillimetres = isMillimetres(image.encoding) && depthScale == kMillimetreScale;
  DepthRaw out(w, h);
  for (int y = 0; y < h; ++y) {
    const uint8_t* row = image.data.data() + static_cast<size_t>(y) * image.step;
    for (int x = 0; x < w; ++x) {
      const uint8_t* p = row + static_cast<size_t>(x) * bytesPerPixel;
      uint16_t raw;
      if (isMetres(image.encoding)) {
        raw = quantise(readPixel<float>(p, swap), depthScale);
      } else {
        const uint16_t mm = readPixel<uint16_t>(p, swap);
        raw = mm == std::numeric_limits<uint16_t>::max() ? 0
              : exactMillimetres                         ? mm
                                                         : quantise(mm / kMillimetreScale, depthScale);
      }
      out(x, y) = raw;
    }
  }
  return out;
}

Intrinsics toIntrinsics(const sensor_msgs::CameraInfo& info, const std::string& where) {
  Intrinsics k;
  k.width = static_cast<int>(info.width);
  k.height = static_cast<int>(info.height);
  k.fx = static_cast<float>(info.K[0]);
  k.fy = static_cast<float>(info.K[4]);
  k.cx = static_cast<float>(info.K[2]);
  k.cy = static_cast<float>(info.K[5]);
  if (info.width == 0 || info.height == 0 || info.width > kMaxDepthImageSide || info.height > kMaxDepthImageSide)
    throw Error(where + ": camera_info size " + std::to_string(info.width) + "x" + std::to_string(info.height) +
                " is outside 1.." + std::to_string(kMaxDepthImageSide) + " pixels per side");
  if (!(k.fx > 0) || !(k.fy > 0) || !std::isfinite(k.cx) || !std::isfinite(k.cy))
    throw Error(where + ": camera_info K has no valid focal length (K = [" + std::to_string(info.K[0]) + ", ..., " +
                std::to_string(info.K[4]) + ", ...]): is the camera calibrated?");
  return k;
}

}  // namespace sb::ros_bridge
