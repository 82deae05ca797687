// The outputs of a long session (issue 34): with a segment store the trajectory and the frame log rotate into
// numbered segments, the summary's ATE reads the trajectory back from them (nothing is kept in memory) and
// agrees with a run that wrote single files, and the report reads only the newest segment; summary.json's
// rewrite on a full disk makes room as the segments' writes do.

#include <sys/mount.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>

#include "core/disk_full.h"
#include "core/rotating_file.h"
#include "core/segment_store.h"
#include "core/trajectory.h"
#include "report/run_data.h"
#include "runtime/line_file.h"
#include "runtime/slam_runner.h"
#include "runtime/standard_outputs.h"
#include "runtime/summary_sink.h"
#include "tests/pipeline/synthetic_room.h"
#include "tests/support/files.h"
#include "tests/support/test_data.h"

namespace {

constexpr size_t kFrames = 240;
constexpr double kFramePeriodS = 1.0 / 30.0;

class FixedController final : public sb::Controller {
 public:
  const std::string& name() const override { return name_; }
  sb::Knobs initialKnobs() const override { return sb::parseKnobs("csr=1,ir=1"); }
  sb::Decision decide(const sb::Observation&) override {
    sb::Decision d;
    d.next = initialKnobs();
    return d;
  }

 private:
  std::string name_ = "fixed";
};

struct Outcome {
  std::optional<sb::AteResult> ate;
  size_t frames = 0;
};

// kFrames of a camera moving 2 mm per frame along x, swaying along y; ground truth written to `groundTruth`
// first.
Outcome runRoom(const std::string& dir, const std::string& groundTruth,
                std::shared_ptr<sb::SegmentStore> segments) {
  sb::test::Room room;
  const sb::Intrinsics k = sb::test::roomIntrinsics(64, 48);
  sb::PipelineConfig config;
  config.volumeSize = 3.0f;
  config.volumeResolution = 32;
  config.bootstrapFrames = 1;
  sb::ThreadPool pool{1};
  auto pipeline = sb::Pipeline::createCpu(config, k, pool);
  sb::Trajectory truth;
  std::vector<sb::DepthFrame> frames;
  for (size_t i = 0; i < kFrames; ++i) {
    Eigen::Isometry3d pose = pipeline->initialPose();
    pose.translation().x() += 0.002 * double(i);
    pose.translation().y() += 0.02 * std::sin(0.05 * double(i));  // not a straight line: ATE needs a plane
    frames.push_back(sb::test::renderRoom(room, pose, k, i));
    frames.back().timestamp = double(i) * kFramePeriodS;
    truth.push_back({frames.back().timestamp, pose});
  }
  sb::writeTumTrajectory(groundTruth, truth);
  sb::SlamRunner runner(*pipeline, std::make_unique<FixedController>(), sb::test::kRoomDepthScale);
  const sb::StandardOutputs outputs = sb::addStandardOutputs(runner, dir, groundTruth, {}, "test", segments);
  for (const sb::DepthFrame& frame : frames) runner.step(frame);
  runner.flush();
  return {outputs.summary->ate(), outputs.summary->stats().frames};
}

}  // namespace

TEST_CASE("rotated outputs: segments, the ATE read back from them, the report from the newest",
          "[runtime][rotation]") {
  const std::string base = sb::test::scratchDir("runtime_rotated");
  const std::string single = base + "/single", rotated = base + "/rotated";
  sb::RetentionLimits limits;
  limits.segmentBytes = 64 * 1024;  // the frame log (~1 KB per frame) needs several
  limits.segmentSeconds = 0;
  limits.minFreeBytes = 0;
  auto segments = std::make_shared<sb::SegmentStore>(base, limits);

  const Outcome a = runRoom(single, base + "/truth.txt", nullptr);
  const Outcome b = runRoom(rotated, base + "/truth.txt", segments);
  REQUIRE(a.ate);
  REQUIRE(b.ate);
  CHECK(b.ate->matches == kFrames);
  CHECK(b.ate->rmse == Approx(a.ate->rmse).margin(1e-9));
  CHECK(b.ate->rmse < 0.01);

  // Replays keep single files; the session's files are segments, each trajectory segment with its header.
  CHECK(std::filesystem::exists(single + "/frames.jsonl"));
  CHECK(std::filesystem::exists(single + "/trajectory.tum"));
  const std::vector<std::string> frameSegments = sb::streamFiles(rotated, "frames.jsonl");
  CHECK(frameSegments.size() >= 3);
  CHECK_FALSE(std::filesystem::exists(rotated + "/frames.jsonl"));
  size_t poses = 0;
  for (const std::string& file : sb::streamFiles(rotated, "trajectory.tum")) {
    std::ifstream in(file);
    std::string first;
    std::getline(in, first);
    CHECK(first.rfind("# timestamp", 0) == 0);
    poses += sb::readTumTrajectory(file).size();
  }
  CHECK(poses == kFrames);

  // The report reads the newest frame-log segment only, and says so.
  const sb::report::RunData run = sb::report::loadRun(rotated);
  CHECK(run.frames.frame.size() > 0);
  CHECK(run.frames.frame.size() < kFrames);
  CHECK(run.frames.frame.back() == double(kFrames - 1));
  bool noted = false;
  for (const std::string& note : run.notes) noted |= note.find("rotated outputs") != std::string::npos;
  CHECK(noted);
}

TEST_CASE("a full disk is a DiskFullError; summary.json's rewrite then removes the oldest segment",
          "[runtime][rotation]") {
  // /dev/full: every write fails with ENOSPC.
  sb::LineFile full("/dev/full", "summary");
  CHECK_THROWS_AS(full.append("{}\n"), sb::DiskFullError);

  // The summary's temporary is a new file of its own name (core/exclusive_file.h; a link planted at a fixed
  // name is never written through, issue 44), so the full disk is a real one: a 64 KiB tmpfs filled by a
  // closed segment (root only, as test_run_reliability's). Its first write finds the disk full and removes
  // the oldest segment. Before, summary.json was not covered by the retention: the first full disk stopped
  // the run (issue 34).
  if (::geteuid() != 0) {
    WARN("not root: the full-disk part needs a tmpfs (mount), skipped");
    return;
  }
  const std::string dir = sb::test::scratchDir("rotation_summary_full");
  REQUIRE(::mount("tmpfs", dir.c_str(), "tmpfs", 0, "size=64k") == 0);
  struct Unmount {
    std::string dir;
    ~Unmount() { ::umount2(dir.c_str(), MNT_DETACH); }
  } unmount{dir};
  const auto fill = [](const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    REQUIRE(f);
    const std::string block(4096, 'x');
    while (std::fwrite(block.data(), 1, block.size(), f) == block.size() && std::fflush(f) == 0) {
    }
    std::fclose(f);
    return std::filesystem::file_size(path);
  };
  sb::RetentionLimits limits;
  limits.minFreeBytes = 0;
  auto store = std::make_shared<sb::SegmentStore>(dir, limits);
  store->addClosed(dir + "/frames-000001.jsonl", fill(dir + "/frames-000001.jsonl"), 1);
  const std::string summaryPath = dir + "/summary.json";
  sb::SummarySink withRetention(summaryPath, "", {}, store);
  CHECK_NOTHROW(withRetention.onFrame(sb::FrameRecord{}));
  CHECK(store->usage().removedSegments == 1);
  CHECK_FALSE(std::filesystem::exists(dir + "/frames-000001.jsonl"));
  CHECK(sb::test::readJson(summaryPath)["frames"] == 1);

  // Without a segment store (a replay) the full disk is the caller's error, naming the file. The room for the
  // last summary is kept from the start (issue 53 finding 8): a disk already full refuses the sink itself.
  sb::SummarySink alone(summaryPath, "", {});
  fill(dir + "/filler");
  CHECK_THROWS_AS(sb::SummarySink(dir + "/other.json", "", {}), sb::DiskFullError);
  CHECK_THROWS_WITH(alone.onFrame(sb::FrameRecord{}),
                    Catch::Contains("summary.json.tmp") && Catch::Contains("keeps the previous summary"));
  CHECK(sb::test::readJson(summaryPath)["frames"] == 1);
}
