// A controller's half-precision wish reaches the OpenCL backend (issue 22's bug: it used to reach only the
// log): SlamRunner switches the backend's storage between frames and records what was requested and applied.

#include <catch2/catch.hpp>
#include <memory>

#include "pipeline/opencl/opencl_backend.h"
#include "pipeline/pipeline.h"
#include "runtime/slam_runner.h"
#include "tests/pipeline/synthetic_room.h"
#include "tests/pipeline/test_opencl_support.h"

namespace {

// Wishes half precision on the frames listed, float elsewhere.
class HalfWisher final : public sb::Controller {
 public:
  explicit HalfWisher(std::vector<bool> wishes) : wishes_(std::move(wishes)) {}
  const std::string& name() const override { return name_; }
  sb::Knobs initialKnobs() const override { return sb::parseKnobs("csr=2,ir=1"); }
  sb::Decision decide(const sb::Observation& o) override {
    sb::Decision d;
    d.next = initialKnobs();
    d.halfPrecision = o.frame < wishes_.size() && wishes_[o.frame];
    return d;
  }

 private:
  std::string name_ = "halfwisher";
  std::vector<bool> wishes_;
};

}  // namespace

TEST_CASE("OpenCL: the controller's half-precision wish switches the backend's storage", "[opencl][half]") {
  const sb::test::Room room;
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  sb::PipelineConfig config;
  config.volumeSize = 3.0f;
  config.volumeResolution = 64;
  config.bootstrapFrames = 1;
  sb::Pipeline pipeline(config, k, std::make_unique<sb::OpenClBackend>(config, k, sb::test::openclTestDevice()));
  // Decisions after frames 1 and 2 wish half: frames 2 and 3 run half, frame 4 float again.
  sb::SlamRunner runner(pipeline, std::make_unique<HalfWisher>(std::vector<bool>{false, true, true, false}),
                        sb::test::kRoomDepthScale);
  std::vector<sb::FrameRecord> records;
  for (size_t i = 0; i < 5; ++i) {
    Eigen::Isometry3d pose = pipeline.initialPose();
    pose.translation().x() += 0.005 * double(i);
    records.push_back(runner.step(sb::test::renderRoom(room, pose, k, i)));
  }
  for (const auto& r : records) CHECK(r.halfSupported);
  CHECK_FALSE(records[1].halfApplied);
  CHECK(records[2].halfRequested);
  CHECK(records[2].halfApplied);
  CHECK(records[3].halfApplied);
  CHECK_FALSE(records[4].halfApplied);
  CHECK_FALSE(pipeline.backend().halfPrecision());
  for (const auto& r : records) CHECK((!r.result.trackingAttempted || r.result.tracked));
}
