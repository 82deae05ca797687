#pragma once
// sensor_msgs/Image and CameraInfo to the project's types, shared by the bag plugin and the depth-topic
// forwarder so that a frame from a bag and the same frame from a topic become the same raw image.
// Encodings (REP 118): 16UC1 (and mono16) millimetres, 32FC1 metres; NaN, inf, <= 0 and readings that do not
// fit the raw range become 0 (no reading).

#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <string>

#include "core/image.h"
#include "core/intrinsics.h"

namespace sb::ros_bridge {

// Raw units per metre a stream gets when nothing else says: 16UC1 keeps its millimetres (1000); 32FC1 is
// quantised to TUM's 0.2 mm (5000; the farthest representable reading is 13.1 m, beyond the far plane).
inline constexpr double kMillimetreScale = 1000.0;
inline constexpr double kFloatMetresScale = 5000.0;

// Whether `encoding` is a depth encoding this project reads.
bool isDepthEncoding(const std::string& encoding);
// The default scale for an encoding (above); only for depth encodings.
double defaultDepthScale(const std::string& encoding);

// Converts `image` to raw units at `depthScale` per metre. Throws sb::Error starting with `where` (file, topic,
// message) naming what is wrong: another encoding, a size past kMaxDepthImageSide, a short data array.
DepthRaw toDepthRaw(const sensor_msgs::Image& image, double depthScale, const std::string& where);

// Intrinsics from CameraInfo's K (fx = K[0], fy = K[4], cx = K[2], cy = K[5]) and its size. Throws sb::Error
// starting with `where` on a zero focal length or a bad size.
Intrinsics toIntrinsics(const sensor_msgs::CameraInfo& info, const std::string& where);

}  // namespace sb::ros_bridge
