#include "odometry/odometry_file.h"

#include <algorithm>
#include <cmath>

namespace sb::odometry {

bool OdometryFileSource::next(OdometrySample& sample) {
  TimedPose p;
  if (!reader_.next(p)) return false;
  sample = OdometrySample{p.timestamp, p.T_camera_to_world, std::nullopt};
  return true;
}

size_t checkOdometryFile(const std::string& path) {
  TumTrajectoryReader reader(path);
  TimedPose p;
  size_t n = 0;
  while (reader.next(p)) ++n;
  return n;
}

OdometryTrack readOdometryFile(const std::string& path, OdometryTrackParams params) {
  const size_t samples = checkOdometryFile(path);  // every line checked before the run uses any
  params.capacity = std::max(params.capacity, std::min(samples, kOdometryFileWindow));
  params.maxLeapS = INFINITY;  // a file's stamps are checked as a whole (increasing), not against a live clock
  return OdometryTrack(params, std::make_unique<OdometryFileSource>(path));
}

}  // namespace sb::odometry
