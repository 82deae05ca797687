// SlamRunner: the controller's knobs reach the next frame, its corrected pose is the one integrated and
// written, pinned knobs and controller switches take effect between frames, and flush() leaves readable
// files at any time.

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/trajectory.h"
#include "runtime/slam_runner.h"
#include "runtime/standard_outputs.h"
#include "tests/pipeline/synthetic_room.h"
#include "tests/support/files.h"
#include "tests/support/test_data.h"

namespace {

// The first fields of the summary of these runs.
sb::RunSummary roomSummary() {
  sb::RunSummary header;
  header.sequence = "room";
  return header;
}

// Plays back a script of decisions and records what it observed.
class ScriptedController final : public sb::Controller {
 public:
  ScriptedController(std::string name, std::vector<sb::Decision> script, sb::Knobs initial)
      : name_(std::move(name)), script_(std::move(script)), initial_(initial) {}
  const std::string& name() const override { return name_; }
  sb::Knobs initialKnobs() const override { return initial_; }
  sb::Decision decide(const sb::Observation& o) override {
    observed.push_back(o);
    depthSeen.push_back(o.depth != nullptr && o.depth->width() > 0);
    return script_.at(std::min(observed.size() - 1, script_.size() - 1));
  }
  std::vector<sb::Observation> observed;
  std::vector<bool> depthSeen;

 private:
  std::string name_;
  std::vector<sb::Decision> script_;
  sb::Knobs initial_;
};

sb::Decision decision(const std::string& knobs) {
  sb::Decision d;
  d.next = sb::parseKnobs(knobs);
  return d;
}

struct Fixture {
  sb::test::Room room;
  sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  sb::PipelineConfig config;
  sb::ThreadPool pool{2};
  std::unique_ptr<sb::Pipeline> pipeline;
  Fixture() {
    config.volumeSize = 3.0f;
    config.volumeResolution = 64;
    config.bootstrapFrames = 1;
    pipeline = sb::Pipeline::createCpu(config, k, pool);
  }
  // Frame i: the camera moves 5 mm per frame along x.
  sb::DepthFrame frame(size_t i) const {
    Eigen::Isometry3d pose = pipeline->initialPose();
    pose.translation().x() += 0.005 * double(i);
    return sb::test::renderRoom(room, pose, k, i);
  }
};

}  // namespace

TEST_CASE("the runner applies the controller's knobs and corrected pose and writes every output", "[runtime]") {
  Fixture f;
  const std::string dir = sb::test::scratchDir("runtime_runner");
  Eigen::Isometry3d jump = f.pipeline->initialPose();
  jump.translation() += Eigen::Vector3d(0.3, 0, 0);
  std::vector<sb::Decision> script = {decision("csr=2"), decision("csr=4,ir=1"), decision("csr=2")};
  script[2].correctedPose = jump;
  script[2].triggers = sb::kTriggerCorrection;
  auto owned = std::make_unique<ScriptedController>("scripted", script, sb::parseKnobs("csr=1"));
  ScriptedController& controller = *owned;
  sb::SlamRunner runner(*f.pipeline, std::move(owned), sb::test::kRoomDepthScale);
  const sb::StandardOutputs outputs = sb::addStandardOutputs(runner, dir, "", roomSummary(), "test");

  std::vector<sb::FrameRecord> records;
  for (size_t i = 0; i < 3; ++i) records.push_back(runner.step(f.frame(i)));
  // Knobs: frame 0 the initial ones, then each frame the previous decision's.
  CHECK(records[0].result.knobs.csr == 1);
  CHECK(records[1].result.knobs.csr == 2);
  CHECK(records[2].result.knobs == sb::parseKnobs("csr=4,ir=1"));
  CHECK(runner.nextKnobs().csr == 2);
  // Observations carry the frame, its tracking and the raw depth.
  REQUIRE(controller.observed.size() == 3);
  CHECK(controller.observed[1].frame == 1);
  CHECK(controller.observed[1].trackingAttempted);
  CHECK(controller.observed[1].tracked);
  CHECK(controller.observed[1].velocity == Approx((records[1].result.T_camera_to_world.translation() -
                                                   records[0].result.T_camera_to_world.translation()).norm()));
  CHECK(controller.observed[2].previousPose.matrix() == records[1].result.T_camera_to_world.matrix());
  CHECK(controller.observed[2].previousComputationMs == Approx(records[1].result.times.computationMs()));
  CHECK(controller.depthSeen == std::vector<bool>{true, true, true});
  // The corrected pose replaced the tracked one.
  CHECK(records[2].result.poseOverridden);
  CHECK(records[2].result.T_camera_to_world.isApprox(jump));
  CHECK(records[2].trackedVelocity == controller.observed[2].velocity);
  CHECK(records[2].result.velocity ==
        Approx((jump.translation() - records[1].result.T_camera_to_world.translation()).norm()));

  // Flush mid-run: the files hold every frame so far.
  runner.flush();
  CHECK(sb::test::dataLines(dir + "/trajectory.tum") == 3);
  CHECK(sb::test::dataLines(dir + "/frames.jsonl") == 3);
  const sb::Trajectory written = sb::readTumTrajectory(dir + "/trajectory.tum");
  CHECK(written[2].T_camera_to_world.translation().isApprox(jump.translation(), 1e-6));
  std::ifstream log(dir + "/frames.jsonl");
  std::string line;
  for (int i = 0; i < 3; ++i) std::getline(log, line);
  const auto last = nlohmann::json::parse(line);
  CHECK(last.at("controller") == "scripted");
  CHECK(last.at("corrected") == true);
  CHECK(last.at("triggers") == nlohmann::json::array({"correction"}));
  CHECK(last.at("knobs").at("csr") == 4);
  CHECK(last.at("next_knobs").at("csr") == 2);
  std::ifstream summaryFile(dir + "/summary.json");
  const auto summary = nlohmann::json::parse(summaryFile);
  CHECK(summary.at("frames") == 3);
  CHECK(summary.at("corrected") == 1);
  CHECK(summary.at("sequence") == "room");
  CHECK(summary.at("triggers").at("correction") == 1);
  CHECK(outputs.summary->stats().frames == 3);
}

TEST_CASE("pinned knobs and a controller switch take effect from the next frame", "[runtime]") {
  Fixture f;
  sb::SlamRunner runner(*f.pipeline,
                        std::make_unique<ScriptedController>("a", std::vector<sb::Decision>{decision("csr=2")},
                                                             sb::parseKnobs("csr=2")),
                        sb::test::kRoomDepthScale);
  CHECK(runner.step(f.frame(0)).result.knobs.csr == 2);
  runner.pinKnobs(sb::parseKnobs("csr=4"));
  const sb::FrameRecord pinned = runner.step(f.frame(1));
  CHECK(pinned.result.knobs.csr == 4);
  CHECK(pinned.knobsPinned);
  CHECK(pinned.decision.next.csr == 4);
  CHECK(runner.step(f.frame(2)).result.knobs.csr == 4);
  runner.pinKnobs(std::nullopt);
  runner.setController(std::make_unique<ScriptedController>("b", std::vector<sb::Decision>{decision("csr=8")},
                                                            sb::parseKnobs("csr=4,ir=1")));
  const sb::FrameRecord switched = runner.step(f.frame(3));
  CHECK(switched.result.knobs == sb::parseKnobs("csr=4,ir=1"));
  CHECK(switched.controller == "b");
  CHECK(runner.nextKnobs().csr == 8);

  sb::Knobs bad;
  bad.csr = 3;
  CHECK_THROWS_AS(runner.pinKnobs(bad), sb::Error);
  runner.setController(std::make_unique<ScriptedController>("broken", std::vector<sb::Decision>{decision("csr=2")},
                                                            sb::parseKnobs("csr=2")));
}

TEST_CASE("partial pins hold their knobs over every choice of the controller, the rest stays its own",
          "[runtime]") {
  Fixture f;
  // The controller alternates its integration rate and compute size every frame.
  std::vector<sb::Decision> script;
  for (int i = 0; i < 6; ++i) script.push_back(decision(i % 2 ? "csr=2,ir=1" : "csr=4,ir=2"));
  sb::SlamRunner runner(*f.pipeline,
                        std::make_unique<ScriptedController>("a", script, sb::parseKnobs("csr=2,ir=1")),
                        sb::test::kRoomDepthScale);
  sb::KnobPins pins;
  pins.pin("csr", 2);
  runner.setPins(pins);  // once: no re-pinning per frame
  std::vector<int> csr, ir;
  for (int i = 0; i < 5; ++i) {
    const sb::FrameRecord r = runner.step(f.frame(size_t(i)));
    csr.push_back(r.result.knobs.csr);
    ir.push_back(r.result.knobs.integrationRate);
    CHECK(r.knobsPinned);
  }
  CHECK(csr == std::vector<int>{2, 2, 2, 2, 2});
  CHECK(ir == std::vector<int>{1, 2, 1, 2, 1});  // the controller's, frame by frame
  runner.setPins(sb::KnobPins{});
  CHECK(runner.nextKnobs().csr == 4);
  CHECK_THROWS_AS(pins.pin("csr", 3), sb::Error);
}

TEST_CASE("a controller that chooses invalid knobs is named in the error", "[runtime]") {
  Fixture f;
  sb::Decision bad;
  bad.next.csr = 5;
  sb::SlamRunner runner(*f.pipeline,
                        std::make_unique<ScriptedController>("broken", std::vector<sb::Decision>{bad}, sb::Knobs{}),
                        sb::test::kRoomDepthScale);
  CHECK_THROWS_WITH(runner.step(f.frame(0)), Catch::Matchers::Contains("controller 'broken'") &&
                                                 Catch::Matchers::Contains("csr"));
}

TEST_CASE("a re-track runs the same frame again with the asked knobs and asks the controller once more", "[runtime]") {
  Fixture f;
  // Frames 0-1: csr=4. Frame 1's first decision asks for a re-track at csr=2; the second keeps csr=4, skips
  // integration and keeps the reference.
  std::vector<sb::Decision> script = {decision("csr=4,ir=1"), decision("csr=4,ir=1"), decision("csr=4,ir=1")};
  script[1].retrack = sb::parseKnobs("csr=2,ir=1");
  script[2].integrate = false;
  script[2].keepReference = true;
  script[2].reason = "because";
  auto owned = std::make_unique<ScriptedController>("scripted", script, sb::parseKnobs("csr=4,ir=1"));
  ScriptedController& controller = *owned;
  sb::SlamRunner runner(*f.pipeline, std::move(owned), sb::test::kRoomDepthScale);
  const std::string dir = sb::test::scratchDir("runtime_retrack");
  sb::addStandardOutputs(runner, dir, "", roomSummary(), "test");
  runner.step(f.frame(0));
  const sb::FrameRecord r = runner.step(f.frame(1));
  REQUIRE(controller.observed.size() == 3);
  CHECK_FALSE(controller.observed[1].retracked);
  CHECK(controller.observed[1].knobs.csr == 4);
  CHECK(controller.observed[2].retracked);
  CHECK(controller.observed[2].knobs.csr == 2);
  CHECK(controller.observed[2].firstKnobs.csr == 4);
  CHECK(controller.observed[2].tracked);
  CHECK(controller.observed[2].quality.known);
  CHECK(r.result.retracked);
  CHECK(r.result.knobs.csr == 2);
  CHECK(r.result.firstKnobs.csr == 4);
  CHECK((r.decision.triggers & sb::kTriggerRetrack) != 0);
  CHECK_FALSE(r.decision.retrack);
  CHECK_FALSE(r.result.integrated);  // the second decision said no
  // The second pass is exactly what tracking the frame at csr=2 in the first place gives.
  Fixture g;
  g.pipeline->processFrame(g.frame(0), sb::test::kRoomDepthScale, sb::parseKnobs("csr=4,ir=1"));
  const sb::FrameResult direct = g.pipeline->trackFrame(g.frame(1), sb::test::kRoomDepthScale, sb::parseKnobs("csr=2,ir=1"));
  CHECK(r.result.T_camera_to_world.matrix() == direct.T_camera_to_world.matrix());
  CHECK(r.result.residual == direct.residual);
  runner.flush();
  std::ifstream log(dir + "/frames.jsonl");
  std::string line;
  std::getline(log, line);
  std::getline(log, line);
  const auto j = nlohmann::json::parse(line);
  CHECK(j.at("retracked_from").at("csr") == 4);
  CHECK(j.at("knobs").at("csr") == 2);
  CHECK(j.at("reason") == "because");
  CHECK(j.at("constrained") == true);
  CHECK(j.at("conditioning").get<double>() > 0.0);
  CHECK(j.at("triggers") == nlohmann::json::array({"retrack"}));
}

TEST_CASE("the controller's start pose is where the next frame's ICP begins; a failure keeps the last pose", "[runtime]") {
  Fixture f, g;
  for (Fixture* x : {&f, &g}) x->pipeline->processFrame(x->frame(0), sb::test::kRoomDepthScale, sb::parseKnobs("csr=2,ir=1"));
  // The same frame from two start poses: the last final pose (no start given) and one 2 cm further along.
  Eigen::Isometry3d ahead = f.pipeline->pose();
  ahead.translation().x() += 0.02;
  sb::FrameResult r = f.pipeline->trackFrame(f.frame(1), sb::test::kRoomDepthScale, sb::parseKnobs("csr=2,ir=1,pd=1:0:0"), sb::IcpStart{ahead});
  const sb::FrameResult plain = g.pipeline->trackFrame(g.frame(1), sb::test::kRoomDepthScale, sb::parseKnobs("csr=2,ir=1,pd=1:0:0"));
  REQUIRE(r.tracked);
  REQUIRE(plain.tracked);
  // One ICP iteration from each start: without the start pose the two would be identical bit for bit.
  CHECK((r.T_camera_to_world.translation() - plain.T_camera_to_world.translation()).norm() > 0.002);
  f.pipeline->finishFrame(r);
  const Eigen::Isometry3d last = r.T_camera_to_world;
  // Started 2 m away (outside the model) ICP finds nothing: the last final pose is kept, not the start.
  Eigen::Isometry3d far = last;
  far.translation().y() += 2.0;
  r = f.pipeline->trackFrame(f.frame(2), sb::test::kRoomDepthScale, sb::parseKnobs("csr=2,ir=1"), sb::IcpStart{far});
  CHECK_FALSE(r.tracked);
  CHECK(r.T_camera_to_world.matrix() == last.matrix());
  f.pipeline->finishFrame(r);
}

TEST_CASE("a frame finished without integration keeps the reference maps when asked", "[runtime]") {
  Fixture f;
  const auto overrides = [](bool integrate, bool keepReference) {  // by name: refinedPose stays unset
    sb::FrameOverrides o;
    o.integrate = integrate;
    o.keepReference = keepReference;
    return o;
  };
  const sb::Knobs k = sb::parseKnobs("csr=2,ir=1");
  f.pipeline->processFrame(f.frame(0), sb::test::kRoomDepthScale, k);
  sb::FrameResult r = f.pipeline->trackFrame(f.frame(1), sb::test::kRoomDepthScale, k);
  REQUIRE(r.tracked);
  f.pipeline->finishFrame(r, std::nullopt, overrides(false, true));
  CHECK_FALSE(r.integrated);
  CHECK(r.times[sb::Stage::integrate] == 0.0);
  CHECK(r.times[sb::Stage::raycast] == 0.0);  // the camera moved, but the reference stays
  // Without keepReference a moved camera raycasts even when nothing was integrated.
  sb::FrameResult s = f.pipeline->trackFrame(f.frame(2), sb::test::kRoomDepthScale, k);
  REQUIRE(s.tracked);  // tracked against the reference of frame 0
  f.pipeline->finishFrame(s, std::nullopt, overrides(false, false));
  CHECK_FALSE(s.integrated);
  CHECK(s.times[sb::Stage::raycast] > 0.0);
  // integrate = true fuses a frame the knobs' rate would skip (ir=1000).
  sb::FrameResult t = f.pipeline->trackFrame(f.frame(3), sb::test::kRoomDepthScale, sb::parseKnobs("csr=2,ir=1000"));
  f.pipeline->finishFrame(t, std::nullopt, overrides(true, false));
  CHECK(t.integrated);
}

TEST_CASE("a refined pose replaces a tracked frame's pose without counting as a correction", "[runtime]") {
  Fixture f;
  const sb::Knobs k = sb::parseKnobs("csr=2,ir=1");
  f.pipeline->processFrame(f.frame(0), sb::test::kRoomDepthScale, k);
  sb::FrameResult r = f.pipeline->trackFrame(f.frame(1), sb::test::kRoomDepthScale, k);
  REQUIRE(r.tracked);
  Eigen::Isometry3d refined = r.T_camera_to_world;
  refined.translation().x() += 0.01;
  sb::FrameOverrides refine;
  refine.integrate = true;
  refine.refinedPose = refined;
  f.pipeline->finishFrame(r, std::nullopt, refine);
  CHECK(r.T_camera_to_world.matrix() == refined.matrix());
  CHECK(f.pipeline->pose().matrix() == refined.matrix());
  CHECK_FALSE(r.poseOverridden);
  // A frame ICP failed keeps the previous pose: a refinement of it is ignored.
  Eigen::Isometry3d far = refined;
  far.translation().y() += 2.0;
  sb::FrameResult lost =
      f.pipeline->trackFrame(f.frame(2), sb::test::kRoomDepthScale, k, sb::IcpStart{far});
  REQUIRE_FALSE(lost.tracked);
  Eigen::Isometry3d elsewhere = far;
  sb::FrameOverrides ignored;
  ignored.integrate = false;
  ignored.refinedPose = elsewhere;
  f.pipeline->finishFrame(lost, std::nullopt, ignored);
  CHECK(lost.T_camera_to_world.matrix() == refined.matrix());
}

TEST_CASE("a half-precision wish on the CPU backend is reported as not supported, not pretended", "[runtime][half]") {
  Fixture f;
  sb::Decision half = decision("csr=2,ir=1");
  half.halfPrecision = true;
  sb::SlamRunner runner(*f.pipeline,
                        std::make_unique<ScriptedController>("halfwish", std::vector<sb::Decision>{half},
                                                             sb::parseKnobs("csr=2,ir=1")),
                        sb::test::kRoomDepthScale);
  const std::string dir = sb::test::scratchDir("runtime_half_cpu");
  sb::addStandardOutputs(runner, dir, "", roomSummary(), "test");
  const sb::FrameRecord first = runner.step(f.frame(0));
  CHECK_FALSE(first.halfRequested);  // nothing wished before the first decision
  const sb::FrameRecord second = runner.step(f.frame(1));
  CHECK(second.halfRequested);
  CHECK_FALSE(second.halfSupported);
  CHECK_FALSE(second.halfApplied);
  runner.flush();
  std::ifstream log(dir + "/frames.jsonl");
  std::string line;
  std::getline(log, line);
  std::getline(log, line);
  CHECK(nlohmann::json::parse(line).at("half") ==
        nlohmann::json({{"requested", true}, {"supported", false}, {"applied", false}}));
  CHECK(sb::test::readJson(dir + "/summary.json").at("half_applied_frames") == 0);
}
