#pragma once
// Writes ROS bags for the tests with the rosbag C++ API, from a sequence on disk (any format openSequence
// reads): depth on /camera/depth/image, its CameraInfo on /camera/depth/camera_info, optionally a small RGB
// image topic beside them (as in TUM RGB-D's bags, so that the depth topic must be chosen by encoding).

#include <string>

namespace sb::test::ros_e2e {

inline constexpr const char* kBagDepthTopic = "/camera/depth/image";
inline constexpr const char* kBagRgbTopic = "/camera/rgb/image_color";

struct BagSpec {
  std::string encoding = "32FC1";  // 32FC1: raw / depth_scale metres (NaN for no reading); 16UC1: raw as mm
                                   // (only for a sequence of depth_scale 1000)
  bool cameraInfo = true;
  bool rgbTopic = true;
};

// Returns the number of depth frames written. Throws std::runtime_error on a 16UC1 request for a sequence
// whose depth scale is not 1000.
size_t writeBag(const std::string& bagPath, const std::string& sequence, const BagSpec& spec);

// Writes `sequence`'s frames as a TUM-layout directory at 1000 raw units per metre (millimetres, rounded).
void writeMillimetreCopy(const std::string& sequence, const std::string& directory);

}  // namespace sb::test::ros_e2e
