#include "ros/map_to_odom.h"

#include <cmath>

namespace sb::ros_bridge {

Eigen::Isometry3d cameraInMap(const PoseReport& pose) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() =
      Eigen::Quaterniond(pose.quaternion[3], pose.quaternion[0], pose.quaternion[1], pose.quaternion[2])
          .normalized()
          .toRotationMatrix();
  T.translation() = Eigen::Vector3d(pose.position[0], pose.position[1], pose.position[2]);
  return T;
}

std::optional<MapOdomStep> MapToOdom::onFrame(uint64_t frame, TrackingState state,
                                              const Eigen::Isometry3d& cameraInMap,
                                              const std::optional<Eigen::Isometry3d>& cameraInOdom) {
  if (state != TrackingState::lost && cameraInOdom) {
    last_ = MapOdomStep{cameraInMap * cameraInOdom->inverse(), MapOdomHold::none, frame};
    return last_;
  }
  if (!last_) return std::nullopt;
  MapOdomStep held = *last_;
  held.hold = state == TrackingState::lost ? MapOdomHold::lost : MapOdomHold::noOdometry;
  return held;
}

std::string describe(const MapOdomStep& step) {
  switch (step.hold) {
    case MapOdomHold::none:
      return "updated";
    case MapOdomHold::lost:
      return "held since frame " + std::to_string(step.sinceFrame) + ": lost";
    case MapOdomHold::noOdometry:
      return "held since frame " + std::to_string(step.sinceFrame) +
             ": no robot odometry at the frame's stamp";
  }
  return "?";
}

int64_t forwardStampNs(int64_t frameStampNs, double toleranceS) {
  return frameStampNs + std::llround(toleranceS * 1e9) + kForwardOffsetNs;
}

}  // namespace sb::ros_bridge
