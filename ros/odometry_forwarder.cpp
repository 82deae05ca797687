#include "ros/odometry_forwarder.h"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/console.h>

#include <cstdio>

#include "client/odometry_pusher.h"
#include "core/error.h"
#include "odometry/camera_mount.h"

namespace sb::ros_bridge {

namespace {

constexpr const char* kDiagnosticName = "slambooster: odometry in";
constexpr double kDiagnosticsPeriodS = 1.0;  // diagnostics' usual rate

diagnostic_msgs::KeyValue keyValue(const std::string& key, const std::string& value) {
  diagnostic_msgs::KeyValue kv;
  kv.key = key;
  kv.value = value;
  return kv;
}

Eigen::Isometry3d toIsometry(double x, double y, double z, const geometry_msgs::Quaternion& q) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(q.w, q.x, q.y, q.z).normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

}  // namespace

OdometryForwarder::OdometryForwarder(ros::NodeHandle& node, const BridgeConfig& config)
    : config_(config), listener_(buffer_) {
  odometry_ = node.subscribe(config.odomTopic, 100, &OdometryForwarder::onOdometry, this);
  diagnostics_ = node.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
  diagnosticsTimer_ = node.createWallTimer(ros::WallDuration(kDiagnosticsPeriodS),
                                           [this](const ros::WallTimerEvent&) { publishDiagnostics(); });
  ROS_INFO("slambooster: odometry from %s (camera mount: tf2 %s), pushed to %s", odometry_.getTopic().c_str(),
           config.odomCameraFrame.c_str(), config.socketPath.c_str());
}

void OdometryForwarder::onOdometry(const nav_msgs::Odometry::ConstPtr& m) {
  std::lock_guard lock(mutex_);
  if (!mount_) {
    try {  // the mount is static: the latest transform
      const auto t = buffer_.lookupTransform(m->child_frame_id, config_.odomCameraFrame, ros::Time(0));
      const auto& r = t.transform.translation;
      const auto& mq = t.transform.rotation;
      if (const std::string problem = odometry::quaternionProblem(mq.w, mq.x, mq.y, mq.z); !problem.empty())
        throw Error("the camera mount from '" + m->child_frame_id + "' to '" + config_.odomCameraFrame + "': " + problem);
      mount_ = toIsometry(r.x, r.y, r.z, mq);
      odomFrame_ = m->header.frame_id;
      baseFrame_ = m->child_frame_id;
    } catch (const std::exception& e) {
      lastError_ = std::string("no camera mount yet: ") + e.what();
      if (++skipped_ == 1 || skipped_ % 100 == 0)
        ROS_WARN("slambooster: odometry skipped (%lu so far): no camera mount yet from '%s' to '%s': %s",
                 static_cast<unsigned long>(skipped_), m->child_frame_id.c_str(), config_.odomCameraFrame.c_str(),
                 e.what());
      return;
    }
  }
  odometry::OdometrySample s;
  s.timestamp = m->header.stamp.toSec();
  // One rule at every door (issue 53): a zero or non-unit orientation is refused, as odometry.txt and ?ODOM
  // refuse it (normalised, zero became identity: a base that never turns).
  const auto& q = m->pose.pose.orientation;
  if (const std::string problem = odometry::quaternionProblem(q.w, q.x, q.y, q.z); !problem.empty()) {
    ++failed_;
    lastError_ = "odometry at " + std::to_string(s.timestamp) + " s refused: pose.orientation: " + problem;
    ROS_WARN_THROTTLE(5.0, "slambooster: %s", lastError_.c_str());
    return;
  }
  const auto& p = m->pose.pose.position;
  s.T_camera_to_odom = toIsometry(p.x, p.y, p.z, m->pose.pose.orientation) * *mount_;
  Eigen::Matrix<double, 6, 6> cov;
  for (int r = 0; r < 6; ++r)
    for (int k = 0; k < 6; ++k) cov(r, k) = m->pose.covariance[static_cast<size_t>(6 * r + k)];
  if (!cov.isZero(0.0)) s.covariance = cov;
  try {
    if (!connection_) connection_ = std::make_unique<client::Connection>(config_.socketPath, config_.connectTimeoutSeconds);
    client::pushOdometry(*connection_, {s}, config_.connectTimeoutSeconds);
    ++pushed_;
    newestPushed_ = s.timestamp;
    lastError_.clear();
  } catch (const Error& e) {
    ++failed_;
    lastError_ = e.what();
    connection_.reset();  // reconnect on the next sample
    ROS_WARN_THROTTLE(5.0, "slambooster: odometry at %.6f s not taken: %s", s.timestamp, e.what());
  }
}

std::optional<RobotFrames> OdometryForwarder::robotFrames() const {
  std::lock_guard lock(mutex_);
  if (!mount_ || odomFrame_.empty()) return std::nullopt;
  return RobotFrames{odomFrame_, baseFrame_, *mount_};
}

std::optional<Eigen::Isometry3d> OdometryForwarder::cameraInOdom(const RobotFrames& frames, const ros::Time& stamp,
                                                                 double waitSeconds, std::string& why) const {
  try {
    // No path at all (a base that publishes /odom but not its TF): say so at once rather than wait each frame.
    if (!buffer_.canTransform(frames.odomFrame, frames.baseFrame, ros::Time(0), &why)) return std::nullopt;
    const auto t = buffer_.lookupTransform(frames.odomFrame, frames.baseFrame, stamp, ros::Duration(waitSeconds));
    const auto& r = t.transform.translation;
    return toIsometry(r.x, r.y, r.z, t.transform.rotation) * frames.cameraInBase;
  } catch (const std::exception& e) {
    why = e.what();
    return std::nullopt;
  }
}

std::optional<std::string> OdometryForwarder::parentInTf(const std::string& frame) const {
  std::string parent;
  if (!buffer_._frameExists(frame) || !buffer_._getParent(frame, ros::Time(0), parent)) return std::nullopt;
  return parent;
}

void OdometryForwarder::publishDiagnostics() {
  diagnostic_msgs::DiagnosticStatus st;
  st.name = kDiagnosticName;
  st.hardware_id = config_.socketPath;
  {
    std::lock_guard lock(mutex_);
    const bool flowing = pushed_ > 0 && lastError_.empty();
    st.level = flowing ? diagnostic_msgs::DiagnosticStatus::OK : diagnostic_msgs::DiagnosticStatus::WARN;
    st.message = flowing ? "odometry reaches slamboosterd"
                         : pushed_ + skipped_ + failed_ == 0 ? "no odometry received on " + odometry_.getTopic()
                                                             : lastError_;
    char newest[32] = "";
    if (newestPushed_) std::snprintf(newest, sizeof newest, "%.6f", *newestPushed_);
    st.values = {keyValue("topic", odometry_.getTopic()), keyValue("camera_frame", config_.odomCameraFrame),
                 keyValue("pushed", std::to_string(pushed_)), keyValue("skipped_no_mount", std::to_string(skipped_)),
                 keyValue("failed", std::to_string(failed_)), keyValue("newest_pushed_s", newest)};
  }
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = ros::Time::now();
  array.status.push_back(std::move(st));
  diagnostics_.publish(array);
}

}  // namespace sb::ros_bridge
