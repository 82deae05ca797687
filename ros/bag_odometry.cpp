#include "ros/bag_odometry.h"

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Image.h>
#include <tf2_msgs/TFMessage.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "core/error.h"
#include "drivers/bag_plugin.h"
#include "odometry/camera_mount.h"
#include "ros/depth_image.h"

namespace sb::ros_bridge {

namespace {

constexpr const char* kOdometryType = "nav_msgs/Odometry";
constexpr const char* kImageType = "sensor_msgs/Image";
constexpr int kMaxChain = 64;  // frames in a /tf_static chain

std::string stripSlash(const std::string& frame) { return !frame.empty() && frame[0] == '/' ? frame.substr(1) : frame; }

Eigen::Isometry3d toIsometry(const geometry_msgs::Point& p, const geometry_msgs::Quaternion& q) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(q.w, q.x, q.y, q.z).normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(p.x, p.y, p.z);
  return T;
}

// The static transforms: child -> (parent, T_child_to_parent, why it cannot be used: empty when it can).
struct StaticLink {
  std::string parent;
  Eigen::Isometry3d T;
  std::string problem;
};
using StaticTree = std::map<std::string, StaticLink>;

StaticTree readStaticTree(rosbag::Bag& bag) {
  StaticTree tree;
  rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{"/tf_static", "tf_static"}));
  for (const rosbag::MessageInstance& m : view) {
    const auto msg = m.instantiate<tf2_msgs::TFMessage>();
    if (!msg) continue;
    for (const auto& t : msg->transforms) {
      geometry_msgs::Point p;
      p.x = t.transform.translation.x;
      p.y = t.transform.translation.y;
      p.z = t.transform.translation.z;
      const auto& q = t.transform.rotation;
      // A zero or non-unit rotation is refused where it is used (as odometry.txt and ?ODOM refuse one), not
      // normalised into something else (zero became identity).
      std::string problem = odometry::quaternionProblem(q.w, q.x, q.y, q.z);
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) problem = "the translation is not finite";
      tree[stripSlash(t.child_frame_id)] = {stripSlash(t.header.frame_id), toIsometry(p, q), problem};
    }
  }
  return tree;
}

// T_frame_to_root and the root's name.
std::pair<Eigen::Isometry3d, std::string> toRoot(const StaticTree& tree, std::string frame) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int i = 0; i < kMaxChain; ++i) {
    const auto it = tree.find(frame);
    if (it == tree.end()) return {T, frame};
    if (!it->second.problem.empty())
      throw Error("/tf_static's transform from '" + it->second.parent + "' to '" + frame + "': " + it->second.problem);
    T = it->second.T * T;
    frame = it->second.parent;
  }
  throw Error("/tf_static has a loop through '" + frame + "'");
}

// The depth images' frame: the first depth-encoded sensor_msgs/Image's header.frame_id.
std::string depthFrame(rosbag::Bag& bag) {
  rosbag::View all(bag);
  for (const rosbag::ConnectionInfo* c : all.getConnections()) {
    if (c->datatype != kImageType) continue;
    rosbag::View v(bag, rosbag::TopicQuery(c->topic));
    if (v.size() == 0) continue;
    const auto image = v.begin()->instantiate<sensor_msgs::Image>();
    if (image && isDepthEncoding(image->encoding)) return stripSlash(image->header.frame_id);
  }
  return "";
}

std::string chooseTopic(rosbag::Bag& bag, const std::string& path, const std::string& requested) {
  rosbag::View all(bag);
  std::set<std::string> topics;
  std::string requestedType;
  for (const rosbag::ConnectionInfo* c : all.getConnections()) {
    if (c->topic == requested) requestedType = c->datatype;
    if (c->datatype == kOdometryType) topics.insert(c->topic);
  }
  if (!requested.empty()) {
    if (requestedType != kOdometryType)
      throw Error("bag '" + path + "': topic '" + requested + "' " +
                  (requestedType.empty() ? "is not in the bag" : "holds " + requestedType) + ", not " + kOdometryType);
    return requested;
  }
  if (topics.size() > 1) {
    std::string names;
    for (const auto& t : topics) names += (names.empty() ? "" : ", ") + t;
    throw Error("bag '" + path + "' has several nav_msgs/Odometry topics (" + names + "): choose one with --odom-topic");
  }
  return topics.empty() ? "" : *topics.begin();
}

}  // namespace

Eigen::Isometry3d parseMount(const std::string& text, const std::string& what) {
  return odometry::parseCameraMount(text, what);  // one rule with the daemon's source.camera_mount
}

std::vector<odometry::OdometrySample> readBagOdometry(const std::string& path, const std::string& requested,
                                                     const std::string& cameraMount, std::string& source) {
  rosbag::Bag bag;
  try {
    bag.open(path, rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    throw Error("cannot read ROS bag '" + path + "': " + e.what());
  }
  std::vector<odometry::OdometrySample> out;
  try {
    const std::string topic = chooseTopic(bag, path, requested);
    if (topic.empty()) return out;
    rosbag::View view(bag, rosbag::TopicQuery(topic));
    std::optional<Eigen::Isometry3d> mount;
    std::string mountFrom = "--camera-mount";
    if (!cameraMount.empty()) mount = parseMount(cameraMount, "--camera-mount");
    const StaticTree tree = mount ? StaticTree{} : readStaticTree(bag);
    const std::string camera = mount ? "" : depthFrame(bag);
    for (const rosbag::MessageInstance& m : view) {
      const auto msg = m.instantiate<nav_msgs::Odometry>();
      if (!msg) continue;
      if (!mount) {  // from /tf_static: the base (the messages' child frame) to the depth camera's frame
        const std::string base = stripSlash(msg->child_frame_id);
        const auto [cameraToRoot, cameraRoot] = toRoot(tree, camera);
        const auto [baseToRoot, baseRoot] = toRoot(tree, base);
        if (camera.empty() || base.empty() || cameraRoot != baseRoot)
          throw Error("bag '" + path + "': no /tf_static chain from '" + base + "' (child_frame_id of " + topic +
                      ") to the depth images' frame '" + camera + "'; give the mount with --camera-mount");
        mount = baseToRoot.inverse() * cameraToRoot;
        mountFrom = "/tf_static " + base + " -> " + camera;
      }
      odometry::OdometrySample s;
      s.timestamp = msg->header.stamp.toSec();
      const auto& q = msg->pose.pose.orientation;
      if (const std::string problem = odometry::quaternionProblem(q.w, q.x, q.y, q.z); !problem.empty()) {
        char at[64];
        std::snprintf(at, sizeof at, "%.6f", s.timestamp);
        throw Error("bag '" + path + "': " + topic + " at " + at + " s: pose.orientation: " + problem +
                    " (a nav_msgs/Odometry's orientation must be a unit quaternion)");
      }
      s.T_camera_to_odom = toIsometry(msg->pose.pose.position, q) * *mount;
      const auto& c = msg->pose.covariance;
      Eigen::Matrix<double, 6, 6> cov;
      for (int r = 0; r < 6; ++r)
        for (int k = 0; k < 6; ++k) cov(r, k) = c[static_cast<size_t>(6 * r + k)];
      if (!cov.isZero(0.0)) s.covariance = cov;  // all zero: the base states none
      out.push_back(s);
    }
    source = path + " " + topic + " (mount: " + mountFrom + ")";
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error("bag '" + path + "': " + e.what() + " (a truncated or damaged bag?)");
  }
  return out;
}

}  // namespace sb::ros_bridge

extern "C" __attribute__((visibility("default"))) void sbReadBagOdometry(
    const std::string& path, const std::string& topic, const std::string& cameraMount,
    std::vector<sb::odometry::OdometrySample>& out, std::string& source) {
  out = sb::ros_bridge::readBagOdometry(path, topic, cameraMount, source);
}
