#pragma once
// For the TF tree tests (issue 57): every edge seen on /tf and /tf_static with who published it, so a test
// can say that no frame has two parents and which node publishes which edge; the bridge's tracking
// diagnostics by frame; the whole watching side of a TF test in one object (TfWatch); and small pose helpers.

#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/Transform.h>
#include <ros/node_handle.h>
#include <ros/spinner.h>
#include <ros/subscriber.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <Eigen/Geometry>
#include <map>
#include <mutex>
#include <optional>
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

// The bridge's tracking diagnostics (/diagnostics, status "slambooster: tracking"), the last one per frame.
class TrackingDiagnostics {
 public:
  void on(const diagnostic_msgs::DiagnosticArray::ConstPtr& message);
  std::optional<diagnostic_msgs::DiagnosticStatus> of(int frame) const;

 private:
  mutable std::mutex mutex_;
  std::map<std::string, diagnostic_msgs::DiagnosticStatus> byFrame_;
};
// A status' value for `key`, or "(no KEY)".
std::string diagnosticValue(const diagnostic_msgs::DiagnosticStatus& status, const std::string& key);

// What a TF test watches, set up in one place: the tracking diagnostics, every TF edge with its publisher, a
// tf2 buffer of 600 s with its listener, and one spinner thread serving them, started on construction.
struct TfWatch {
  explicit TfWatch(ros::NodeHandle& node);
  TrackingDiagnostics diagnostics;
  ros::Subscriber diagnosticsSub;
  TfRecorder recorder;
  tf2_ros::Buffer buffer{ros::Duration(600)};
  tf2_ros::TransformListener listener{buffer};
  ros::AsyncSpinner spinner{1};
};

Eigen::Isometry3d toIsometry(const geometry_msgs::Transform& t);
geometry_msgs::Transform toTransform(const Eigen::Isometry3d& T);
// "x y z qx qy qz qw" as a pose.
Eigen::Isometry3d parsePose(const std::string& text);
double translationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);  // metres
double rotationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);     // radians

}  // namespace sb::test::ros_e2e
