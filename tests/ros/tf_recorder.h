#pragma once
// For the TF tree tests (issue 57): every edge seen on /tf and /tf_static with who published it, so a test
// can say that no frame has two parents and which node publishes which edge; and small pose helpers.

#include <geometry_msgs/Transform.h>
#include <ros/node_handle.h>
#include <ros/subscriber.h>
#include <tf2_msgs/TFMessage.h>

#include <Eigen/Geometry>
#include <map>
#include <mutex>
#include <set>
#include <string>

namespace sb::test::ros_e2e {

class TfRecorder {
 public:
  explicit TfRecorder(ros::NodeHandle& node);
  // child frame -> the parents it was published under (more than one: the tree is broken).
  std::map<std::string, std::set<std::string>> parents() const;
  // "parent -> child" edges that node `publisher` (e.g. "/slambooster") published.
  std::set<std::string> edgesOf(const std::string& publisher) const;

 private:
  void onTf(const ros::MessageEvent<tf2_msgs::TFMessage const>& event);

  mutable std::mutex mutex_;
  std::map<std::string, std::set<std::string>> parents_;
  std::map<std::string, std::set<std::string>> edges_;  // publisher -> edges
  ros::Subscriber tf_, tfStatic_;
};

Eigen::Isometry3d toIsometry(const geometry_msgs::Transform& t);
geometry_msgs::Transform toTransform(const Eigen::Isometry3d& T);
// "x y z qx qy qz qw" as a pose.
Eigen::Isometry3d parsePose(const std::string& text);
double translationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);  // metres
double rotationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);     // radians

}  // namespace sb::test::ros_e2e
