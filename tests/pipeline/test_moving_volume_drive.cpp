// The moving volume in the pipeline (pipeline/volume_window.h), in process: a drive of 3.2 m along the long axis of the
// synth living room (camera 1.25 m above the floor looking sideways at the furnished wall 1.5 m away, weaving
// +-10 cm across the axis, 2.5 cm/frame), tracked in a 2 m volume (64^3) that the camera leaves after about a
// metre. With the volume fixed the model falls
// behind the camera and tracking is lost; with the moving volume the run tracks and its trajectory stays
// close to the truth.

#include <catch2/catch.hpp>
#include <cmath>

#include "core/trajectory.h"
#include "eval/trajectory_eval.h"
#include "pipeline/pipeline.h"
#include "synth/renderer.h"
#include "synth/scene_generator.h"
#include "synth/synth_sequence.h"

namespace {

constexpr int kFrames = 129;
constexpr double kStepM = 0.025;  // metres per frame (0.75 m/s at 30 Hz)

struct Drive {
  sb::Intrinsics k;
  std::vector<sb::DepthFrame> frames;
  sb::Trajectory truth;
};

const Drive& drive() {
  static const Drive d = [] {
    Drive r;
    const sb::synth::Scene scene = sb::synth::generateScene("livingroom", 7);
    r.k = sb::synth::iclNuimIntrinsics().scaled(4);  // 160x120
    const sb::synth::Renderer renderer(scene, r.k);
    const sb::synth::SensorModel sensor;
    for (int i = 0; i < kFrames; ++i) {
      // Looking along -x (image y down, floor at +y), moving along +z (to the right in the image).
      Eigen::Isometry3d pose(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitY()));
      pose.translation() = Eigen::Vector3d(-1.0 + 0.1 * std::sin(i * 0.05), 0.0, -3.0 + kStepM * i);
      r.truth.push_back({i / 30.0, pose});
      sb::DepthMeters metres;
      renderer.render(pose, sensor, sb::synth::frameSeed(11, size_t(i)), metres);
      sb::DepthFrame frame;
      frame.index = size_t(i);
      frame.timestamp = i / 30.0;
      sb::synth::toRaw(metres, sb::synth::kIclDepthScale, frame.depth);
      r.frames.push_back(std::move(frame));
    }
    return r;
  }();
  return d;
}

struct DriveResult {
  double trackedFraction = 0, ateM = 0;
  size_t shifts = 0;
};

DriveResult runDrive(bool moving) {
  sb::PipelineConfig config;
  config.volumeResolution = 64;
  config.volumeSize = 2.0f;
  config.initialPosition = {0.2f, 0.5f, 0.2f};  // the wall 1.5 m ahead is inside; the drive goes along +x
  config.volumeMode = moving ? sb::VolumeMode::moving : sb::VolumeMode::fixed;
  config.volumeShiftThreshold = 0.5f;  // a quarter of the side
  config.volumeViewDistance = 0.6f;
  config.backend = sb::BackendKind::cpu;
  sb::ThreadPool pool(2);
  const auto pipeline = sb::Pipeline::createCpu(config, drive().k, pool);
  sb::Trajectory estimate;
  size_t tracked = 0, attempted = 0;
  for (const sb::DepthFrame& frame : drive().frames) {
    const sb::FrameResult r = pipeline->processFrame(frame, sb::synth::kIclDepthScale, config.knobs);
    estimate.push_back({r.timestamp, r.T_camera_to_world});
    tracked += r.tracked;
    attempted += r.trackingAttempted;
  }
  DriveResult result;
  result.trackedFraction = double(tracked) / double(attempted);
  result.ateM = sb::computeAte(estimate, drive().truth).rmse;
  if (pipeline->volumeWindow()) result.shifts = pipeline->volumeWindow()->stats().shifts;
  return result;
}

}  // namespace

TEST_CASE("a drive longer than the volume tracks with the moving volume and not with a fixed one",
          "[volume_window][system]") {
  const DriveResult fixed = runDrive(false);
  const DriveResult moving = runDrive(true);
  INFO("fixed: tracked " << fixed.trackedFraction << ", ATE " << fixed.ateM << " m; moving: tracked "
                         << moving.trackedFraction << ", ATE " << moving.ateM << " m, " << moving.shifts << " shifts");
  CHECK(moving.shifts >= 3);
  CHECK(moving.trackedFraction >= 0.99);
  CHECK(moving.ateM < 0.03);
  CHECK((fixed.trackedFraction < 0.8 || fixed.ateM > 0.2));
}
