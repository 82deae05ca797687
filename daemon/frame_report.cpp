#include "daemon/frame_report.h"

#include <Eigen/Geometry>

namespace sb::daemon {

FrameReport frameReport(const FrameRecord& rec, std::vector<std::string> pinned) {
  const FrameResult& r = rec.result;
  FrameReport report;
  PoseFields& p = report.pose;
  p.frame = r.frame;
  p.timestamp = r.timestamp;
  const Eigen::Vector3d t = r.T_camera_to_world.translation();
  const Eigen::Quaterniond q(r.T_camera_to_world.rotation());
  p.position = {t.x(), t.y(), t.z()};
  p.quaternion = {q.x(), q.y(), q.z(), q.w()};
  p.tracked = r.tracked;
  p.corrected = r.poseOverridden;
  p.state = rec.state;
  p.velocityMPerFrame = r.velocity;
  if (r.quality.known) {
    p.conditioning = r.quality.conditioning;
    p.weakestMotion = weakDirectionName(r.quality.weakest);
    p.constrained = r.quality.constrained;
  }
  p.odometry = rec.odometry.available;
  p.odometryDriftM = rec.odometry.driftM;
  if (rec.odometry.fault != odometry::WheelFault::none) p.odometryFault = odometry::wheelFaultName(rec.odometry.fault);
  if (rec.keptMap != KeptMap::none) p.keptMap = keptMapName(rec.keptMap);
  KnobFields& k = report.knobs;
  k.frame = r.frame;
  k.controller = rec.controller;
  k.computationMs = r.times.computationMs();
  k.knobs = r.knobs;
  report.pinned = std::move(pinned);
  return report;
}

}  // namespace sb::daemon
