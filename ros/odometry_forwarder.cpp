#include "ros/odometry_forwarder.h"

#include <ros/console.h>

#include "client/odometry_pusher.h"
#include "core/error.h"

namespace sb::ros_bridge {

namespace {

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
  ROS_INFO("slambooster: odometry from %s (camera mount: tf2 %s), pushed to %s", odometry_.getTopic().c_str(),
           config.odomCameraFrame.c_str(), config.socketPath.c_str());
}

void OdometryForwarder::onOdometry(const nav_msgs::Odometry::ConstPtr& m) {
  std::lock_guard lock(mutex_);
  if (!mount_) {
    try {  // the mount is static: the latest transform
      const auto t = buffer_.lookupTransform(m->child_frame_id, config_.odomCameraFrame, ros::Time(0));
      const auto& r = t.transform.translation;
      mount_ = toIsometry(r.x, r.y, r.z, t.transform.rotation);
    } catch (const std::exception& e) {
      if (++skipped_ == 1 || skipped_ % 100 == 0)
        ROS_WARN("slambooster: odometry skipped (%lu so far): no camera mount yet from '%s' to '%s': %s",
                 static_cast<unsigned long>(skipped_), m->child_frame_id.c_str(), config_.odomCameraFrame.c_str(),
                 e.what());
      return;
    }
  }
  odometry::OdometrySample s;
  s.timestamp = m->header.stamp.toSec();
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
  } catch (const Error& e) {
    connection_.reset();  // reconnect on the next sample
    ROS_WARN_THROTTLE(5.0, "slambooster: odometry at %.6f s not taken: %s", s.timestamp, e.what());
  }
}

}  // namespace sb::ros_bridge
