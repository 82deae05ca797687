#include "tests/ros/tf_recorder.h"

#include <sstream>
#include <stdexcept>

namespace sb::test::ros_e2e {

TfRecorder::TfRecorder(ros::NodeHandle& node) {
  tf_ = node.subscribe("/tf", 1000, &TfRecorder::onTf, this);
  tfStatic_ = node.subscribe("/tf_static", 100, &TfRecorder::onTf, this);
}

void TfRecorder::onTf(const ros::MessageEvent<tf2_msgs::TFMessage const>& event) {
  std::lock_guard lock(mutex_);
  for (const auto& t : event.getMessage()->transforms) {
    parents_[t.child_frame_id].insert(t.header.frame_id);
    edges_[event.getPublisherName()].insert(t.header.frame_id + " -> " + t.child_frame_id);
  }
}

std::map<std::string, std::set<std::string>> TfRecorder::parents() const {
  std::lock_guard lock(mutex_);
  return parents_;
}

std::set<std::string> TfRecorder::edgesOf(const std::string& publisher) const {
  std::lock_guard lock(mutex_);
  const auto it = edges_.find(publisher);
  return it == edges_.end() ? std::set<std::string>{} : it->second;
}

void TrackingDiagnostics::on(const diagnostic_msgs::DiagnosticArray::ConstPtr& message) {
  std::lock_guard lock(mutex_);
  for (const auto& s : message->status)
    if (s.name == "slambooster: tracking")
      for (const auto& kv : s.values)
        if (kv.key == "frame") byFrame_[kv.value] = s;
}

std::optional<diagnostic_msgs::DiagnosticStatus> TrackingDiagnostics::of(int frame) const {
  std::lock_guard lock(mutex_);
  const auto it = byFrame_.find(std::to_string(frame));
  return it == byFrame_.end() ? std::nullopt : std::optional(it->second);
}

std::string diagnosticValue(const diagnostic_msgs::DiagnosticStatus& status, const std::string& key) {
  for (const auto& kv : status.values)
    if (kv.key == key) return kv.value;
  return "(no " + key + ")";
}

TfWatch::TfWatch(ros::NodeHandle& node)
    : diagnosticsSub(node.subscribe("/diagnostics", 100, &TrackingDiagnostics::on, &diagnostics)), recorder(node) {
  spinner.start();
}

Eigen::Isometry3d toIsometry(const geometry_msgs::Transform& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z);
  return T;
}

geometry_msgs::Transform toTransform(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.linear());
  geometry_msgs::Transform t;
  t.translation.x = T.translation().x();
  t.translation.y = T.translation().y();
  t.translation.z = T.translation().z();
  t.rotation.x = q.x();
  t.rotation.y = q.y();
  t.rotation.z = q.z();
  t.rotation.w = q.w();
  return t;
}

Eigen::Isometry3d parsePose(const std::string& text) {
  std::istringstream in(text);
  double v[7];
  for (double& x : v) in >> x;
  if (!in) throw std::runtime_error("not a pose 'x y z qx qy qz qw': " + text);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(v[6], v[3], v[4], v[5]).normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  return T;
}

double translationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.translation() - b.translation()).norm();
}

double rotationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}

}  // namespace sb::test::ros_e2e
