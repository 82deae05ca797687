#pragma once
// Writes ROS bags for the tests with the rosbag C++ API, from a sequence on disk (any format openSequence
// reads): depth on /camera/depth/image, its CameraInfo on /camera/depth/camera_info, optionally a small RGB
// image topic beside them (as in TUM RGB-D's bags, so that the depth topic must be chosen by encoding).

#include <nav_msgs/Odometry.h>
#include <tf2_msgs/TFMessage.h>

#include <limits>
#include <string>
#include <vector>

namespace sb::test::ros_e2e {

inline constexpr const char* kBagDepthTopic = "/camera/depth/image";
inline constexpr const char* kBagRgbTopic = "/camera/rgb/image_color";

struct BagSpec {
  std::string encoding = "32FC1";  // 32FC1: raw / depth_scale metres (NaN for no reading); 16UC1: raw as mm
                                   // (only for a sequence of depth_scale 1000)
  bool cameraInfo = true;
  bool rgbTopic = true;
  // An odometry.txt (T_camera_to_odom) to write as nav_msgs/Odometry on /odom (child frame base_link), with
  // /tf_static base_link -> the depth images' frame (kBagCameraMount) unless tfStatic is false.
  std::string odometryFile;
  bool tfStatic = true;
  // The same poses also as odom -> base_link on /tf, as a robot's bag records them (its base driver's TF).
  bool odomTf = false;
  // Hostile orientations (issue 53 finding 4): the 10th Odometry message's, or /tf_static's mount, all zero.
  bool zeroOdometryQuaternion = false;
  bool zeroMountQuaternion = false;
  // Hostile bags (issue 44 G3, G4): the CameraInfo's K[0] (fx) when not NaN; the depth images' header
  // stamps when not empty (one per frame; the record times stay the sequence's: the frames keep their order).
  double cameraInfoFx = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> stamps;
};

// The camera mount the bags' /tf_static states ("x y z qx qy qz qw": 1.25 m up, optical axes; exact in binary).
inline constexpr const char* kBagCameraMount = "0 0 1.25 -0.5 0.5 -0.5 0.5";

// The mount as /tf_static states it: base_link -> `cameraFrame`, stamped `stamp`.
tf2_msgs::TFMessage cameraMountMessage(const std::string& cameraFrame, const ros::Time& stamp);

// An odometry.txt (T_camera_to_odom) as the base's nav_msgs/Odometry (frame odom, child base_link): each
// camera pose less kBagCameraMount, stamped with its timestamp; with `covariance` a stated pose covariance.
std::vector<nav_msgs::Odometry> odometryMessages(const std::string& odometryFile, bool covariance);

// Returns the number of depth frames written. Throws std::runtime_error on a 16UC1 request for a sequence
// whose depth scale is not 1000.
size_t writeBag(const std::string& bagPath, const std::string& sequence, const BagSpec& spec);

// Writes `sequence`'s frames as a TUM-layout directory at 1000 raw units per metre (millimetres, rounded).
void writeMillimetreCopy(const std::string& sequence, const std::string& directory);

}  // namespace sb::test::ros_e2e
