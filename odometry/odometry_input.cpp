#include "odometry/odometry_input.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "drivers/bag_loader.h"

namespace sb {

namespace fs = std::filesystem;

std::optional<OdometrySummary> OdometryInput::summary() const {
  if (!track) return std::nullopt;
  OdometrySummary s;
  s.source = source;
  s.samples = track->size();
  return s;
}

namespace {

OdometryInput fromFile(const std::string& path) {
  auto track = std::make_shared<odometry::OdometryTrack>(odometry::readOdometryFile(path));
  if (track->size() == 0) throw Error(path + ": no odometry samples (expected lines 'timestamp tx ty tz qx qy qz qw')");
  return OdometryInput{std::move(track), path};
}

OdometryInput fromBag(const std::string& path, const BagOdometryOptions& options, bool required) {
  std::string source;
  std::vector<odometry::OdometrySample> samples = readBagOdometry(path, options.topic, options.cameraMount, &source);
  if (samples.empty()) {
    if (required) throw Error(path + ": no nav_msgs/Odometry messages" +
                              (options.topic.empty() ? std::string() : " on " + options.topic));
    return {};
  }
  odometry::OdometryTrackParams params;
  params.capacity = std::max(params.capacity, samples.size());
  params.maxLeapS = INFINITY;  // a recorded file: its stamps need only increase (odometry_track.h's leap rule is the live doors')
  auto track = std::make_shared<odometry::OdometryTrack>(params);
  for (const odometry::OdometrySample& s : samples) {
    std::string why;
    if (!track->add(s, &why)) throw Error(path + " (" + source + "): " + why);
  }
  return OdometryInput{std::move(track), source};
}

}  // namespace

OdometryInput openOdometry(const std::string& choice, const std::string& sequence, const BagOdometryOptions& bag) {
  if (choice == "none") return {};
  const fs::path seq(sequence);
  const bool isBag = seq.extension() == ".bag";
  if (choice == "auto") {
    if (isBag) return fromBag(sequence, bag, !bag.topic.empty());
    std::error_code ec;
    const fs::path dir = fs::is_directory(seq, ec) ? seq : seq.parent_path();  // a TUM directory or its depth.txt
    const fs::path file = dir / kOdometryFileName;
    if (!sequence.empty() && fs::is_regular_file(file, ec)) return fromFile(file.string());
    return {};
  }
  if (choice.empty()) throw Error("odometry: give \"auto\", \"none\" or the path of an odometry.txt");
  if (fs::path(choice).extension() == ".bag") return fromBag(choice, bag, true);
  return fromFile(choice);
}

OdometryInput liveOdometry(const std::string& source) {
  return OdometryInput{std::make_shared<odometry::OdometryTrack>(), source};
}

void countOdometryFrame(const odometry::OdometryTrack& track, double timestamp, OdometrySummary& summary,
                        std::optional<Eigen::Isometry3d>& last) {
  summary.samples = track.size();
  const std::optional<Eigen::Isometry3d> pose = track.poseAt(timestamp);
  if (!pose) return;
  ++summary.framesWithPose;
  if (last) summary.pathM += (pose->translation() - last->translation()).norm();
  last = pose;
}

void noteCalibration(const odometry::MotionModel& model, OdometrySummary& summary) {
  const odometry::CalibrationEstimate e = model.calibration().estimate();
  const odometry::MountCalibration& mount = model.mount();
  summary.timeOffsetS = model.timeOffset().offset();
  summary.timeOffsetLearnt = model.timeOffset().learnt();
  summary.mountErrorDeg = mount.errorDeg();
  summary.mountLearntFrom = mount.source();
  summary.mountTurnSeenDeg = mount.turnSeenDeg();
  summary.mountFloorFrames = mount.floorFrames();
  summary.scaleError = e.scale;
  summary.yawScaleError = e.yawScale;
  summary.yawBiasDegPerS = e.yawBiasRadPerS * 180.0 / 3.14159265358979323846;
  summary.calibrationFrames = static_cast<size_t>(e.frames);
}

}  // namespace sb
