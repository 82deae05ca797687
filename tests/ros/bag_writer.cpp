#include "tests/ros/bag_writer.h"

#include <Eigen/Geometry>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <tf2_msgs/TFMessage.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "drivers/sequence.h"
#include "core/trajectory.h"
#include "drivers/tum_writer.h"

namespace sb::test::ros_e2e {

namespace {

constexpr double kMillimetres = 1000.0;
constexpr double kRecordDelayS = 0.01;

std::unique_ptr<FrameSource> openPlain(const std::string& sequence) {
  SequenceOptions o;
  o.prefetch = false;
  return openSequence(sequence, o);
}

Eigen::Isometry3d mount() {
  std::istringstream in(kBagCameraMount);
  double v[7];
  for (double& x : v) in >> x;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(v[6], v[3], v[4], v[5]).toRotationMatrix();
  T.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  return T;
}

// The base's odometry (the camera's poses less the mount) on /odom, and the mount on /tf_static.
void writeOdometry(rosbag::Bag& bag, const BagSpec& spec) {
  const ros::Time start(kRecordDelayS);
  if (spec.tfStatic) {
    tf2_msgs::TFMessage tf = cameraMountMessage("openni_depth_optical_frame", start);
    if (spec.zeroMountQuaternion) tf.transforms[0].transform.rotation = geometry_msgs::Quaternion();  // all zero
    bag.write("/tf_static", start, tf);
  }
  std::vector<nav_msgs::Odometry> messages = odometryMessages(spec.odometryFile, /*covariance=*/true);
  if (spec.zeroOdometryQuaternion && messages.size() > 10) messages[10].pose.pose.orientation = geometry_msgs::Quaternion();
  for (const nav_msgs::Odometry& o : messages) {
    bag.write("/odom", o.header.stamp + ros::Duration(kRecordDelayS), o);
    if (!spec.odomTf) continue;
    geometry_msgs::TransformStamped t;
    t.header = o.header;
    t.child_frame_id = o.child_frame_id;
    t.transform.translation.x = o.pose.pose.position.x;
    t.transform.translation.y = o.pose.pose.position.y;
    t.transform.translation.z = o.pose.pose.position.z;
    t.transform.rotation = o.pose.pose.orientation;
    tf2_msgs::TFMessage tf;
    tf.transforms.push_back(t);
    bag.write("/tf", o.header.stamp + ros::Duration(kRecordDelayS), tf);
  }
}

}  // namespace

tf2_msgs::TFMessage cameraMountMessage(const std::string& cameraFrame, const ros::Time& stamp) {
  const Eigen::Isometry3d M = mount();
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = "base_link";
  t.child_frame_id = cameraFrame;
  const Eigen::Quaterniond q(M.rotation());
  t.transform.translation.x = M.translation().x();
  t.transform.translation.y = M.translation().y();
  t.transform.translation.z = M.translation().z();
  t.transform.rotation.x = q.x();
  t.transform.rotation.y = q.y();
  t.transform.rotation.z = q.z();
  t.transform.rotation.w = q.w();
  tf2_msgs::TFMessage tf;
  tf.transforms.push_back(t);
  return tf;
}

std::vector<nav_msgs::Odometry> odometryMessages(const std::string& odometryFile, bool covariance) {
  const Eigen::Isometry3d M = mount();
  std::vector<nav_msgs::Odometry> out;
  for (const TimedPose& p : readTumTrajectory(odometryFile)) {
    const Eigen::Isometry3d base = p.T_camera_to_world * M.inverse();
    nav_msgs::Odometry o;
    o.header.stamp = ros::Time(p.timestamp);
    o.header.seq = static_cast<uint32_t>(out.size());
    o.header.frame_id = "odom";
    o.child_frame_id = "base_link";
    const Eigen::Quaterniond q(base.rotation());
    o.pose.pose.position.x = base.translation().x();
    o.pose.pose.position.y = base.translation().y();
    o.pose.pose.position.z = base.translation().z();
    o.pose.pose.orientation.x = q.x();
    o.pose.pose.orientation.y = q.y();
    o.pose.pose.orientation.z = q.z();
    o.pose.pose.orientation.w = q.w();
    if (covariance) {
      o.pose.covariance[0] = o.pose.covariance[7] = 1e-4;  // x, y; the rest unknown (large)
      o.pose.covariance[14] = o.pose.covariance[21] = o.pose.covariance[28] = 1e6;
      o.pose.covariance[35] = 1e-3;
    }
    out.push_back(std::move(o));
  }
  return out;
}

size_t writeBag(const std::string& bagPath, const std::string& sequence, const BagSpec& spec) {
  auto source = openPlain(sequence);
  const SequenceInfo info = source->info();
  if (spec.encoding == "16UC1" && info.depthScale != kMillimetres)
    throw std::runtime_error("a 16UC1 bag needs a millimetre sequence");
  rosbag::Bag bag(bagPath, rosbag::bagmode::Write);
  size_t n = 0;
  while (auto f = source->next()) {
    // When the recorder received it: a little later, and after ros::TIME_MIN (a synthetic frame 0 is at 0 s).
    const ros::Time recorded = ros::Time(f->timestamp) + ros::Duration(kRecordDelayS);
    const ros::Time stamp(n < spec.stamps.size() ? spec.stamps[n] : f->timestamp);
    sensor_msgs::Image image;
    image.header.stamp = stamp;
    image.header.seq = static_cast<uint32_t>(n);
    image.header.frame_id = "openni_depth_optical_frame";
    image.width = static_cast<uint32_t>(f->depth.width());
    image.height = static_cast<uint32_t>(f->depth.height());
    image.encoding = spec.encoding;
    if (spec.encoding == "32FC1") {
      image.step = image.width * sizeof(float);
      image.data.resize(static_cast<size_t>(image.step) * image.height);
      for (size_t i = 0; i < f->depth.size(); ++i) {
        const uint16_t raw = f->depth.pixels()[i];
        const float m = raw ? static_cast<float>(raw / info.depthScale) : std::numeric_limits<float>::quiet_NaN();
        std::memcpy(image.data.data() + i * sizeof(float), &m, sizeof m);
      }
    } else {
      image.step = image.width * sizeof(uint16_t);
      image.data.resize(static_cast<size_t>(image.step) * image.height);
      std::memcpy(image.data.data(), f->depth.data(), image.data.size());
    }
    bag.write(kBagDepthTopic, recorded, image);
    if (spec.cameraInfo) {
      sensor_msgs::CameraInfo ci;
      ci.header = image.header;
      ci.width = image.width;
      ci.height = image.height;
      ci.K = {info.intrinsics.fx, 0, info.intrinsics.cx, 0, info.intrinsics.fy, info.intrinsics.cy, 0, 0, 1};
      if (!std::isnan(spec.cameraInfoFx)) ci.K[0] = spec.cameraInfoFx;
      bag.write("/camera/depth/camera_info", recorded, ci);
    }
    if (spec.rgbTopic) {
      sensor_msgs::Image rgb;
      rgb.header = image.header;
      rgb.width = 4;
      rgb.height = 4;
      rgb.encoding = "rgb8";
      rgb.step = 12;
      rgb.data.assign(48, 128);
      bag.write(kBagRgbTopic, recorded, rgb);
    }
    ++n;
  }
  if (!spec.odometryFile.empty()) writeOdometry(bag, spec);
  bag.close();
  return n;
}

void writeMillimetreCopy(const std::string& sequence, const std::string& directory) {
  auto source = openPlain(sequence);
  SequenceInfo info = source->info();
  const double scale = info.depthScale;
  info.depthScale = kMillimetres;
  TumSequenceWriter writer(directory, info);
  while (auto f = source->next()) {
    for (auto& v : f->depth.pixels()) v = static_cast<uint16_t>(std::lround(v * kMillimetres / scale));
    writer.write(*f);
  }
  writer.finish();
}

}  // namespace sb::test::ros_e2e
