// The state a map store keeps beside the TSDF and the keyframes (issue 55; runtime/map_store_format.h): a state
// file (navmap.bin, odometry.bin) round-trips through the store and is refused at open, naming it, when truncated,
// altered, foreign (another magic) or of another format version; the wheels' learnt calibration
// (runtime/kept_odometry.h) round-trips whole (the next run's estimate is the kept one's, its clock offset the kept
// one's when its config takes it, the mount it was learnt against recorded) and a payload that is not a calibration
// is refused naming the file; an odometry.bin of version 1 (before the clock offset and the mount were kept) is
// read as what it holds, a newer one refused.

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "runtime/kept_odometry.h"
#include "runtime/map_store.h"
#include "runtime/map_store_bytes.h"
#include "tests/support/test_data.h"
#include "tests/support/store_files.h"

namespace fs = std::filesystem;

using sb::test::bytesOf;
using sb::test::writeBytes;
using sb::test::refusal;

namespace {

sb::PipelineConfig smallConfig() {
  sb::PipelineConfig c;
  c.volumeResolution = 64;
  c.volumeSize = 4.0f;
  c.volumeMode = sb::VolumeMode::moving;
  return c;
}

// A calibration that has learnt something: 2% long, turns 3% large, a drift, and a mount 1.5 degrees off.
sb::KeptOdometry learnt() {
  sb::KeptOdometry k;
  sb::odometry::OdometryConfig config;
  k.calibration = sb::odometry::OdometryCalibration(config).state();
  k.calibration.scaleInfo *= 40.0;
  k.calibration.scaleVec = 0.02 * k.calibration.scaleInfo;
  k.calibration.yawInfo = k.calibration.yawInfo * 30.0 + Eigen::Matrix2d::Constant(5.0);
  k.calibration.yawVec = k.calibration.yawInfo * Eigen::Vector2d(0.03, 0.001);
  k.calibration.frames = 412;
  k.mount.correction = Eigen::AngleAxisd(1.5 * M_PI / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  k.mount.turnRad = 4.2;
  k.mount.weights = 4.2;
  k.mount.standardError = 0.002;
  k.mount.viewSum = Eigen::Vector3d(0.1, 4.1, 0.2);
  k.mount.wheelSum = Eigen::Vector3d(0.0, 4.2, 0.0);
  k.mount.floorFrames = 300;
  k.mount.floorSpreadRad = 0.004;
  k.mount.fromFloor = true;
  k.timeOffset = {0.045, true, 288};
  k.mountUp = Eigen::Vector3d(0.0, -0.9994, 0.0349).normalized();  // a camera pitched 2 degrees
  return k;
}

}  // namespace

TEST_CASE("the wheels' calibration round-trips whole and a payload that is not one is refused naming the file",
          "[map_store]") {
  const sb::KeptOdometry k = learnt();
  const std::vector<uint8_t> payload = sb::encodeKeptOdometry(k);
  CHECK(payload.size() == 316);
  const sb::KeptOdometry back = sb::decodeKeptOdometry(payload, "S/odometry.bin", 2);
  CHECK(back.calibration.scaleInfo == k.calibration.scaleInfo);
  CHECK(back.calibration.yawInfo == k.calibration.yawInfo);
  CHECK(back.calibration.yawVec == k.calibration.yawVec);
  CHECK(back.calibration.frames == 412);
  CHECK(back.mount.correction == k.mount.correction);
  CHECK(back.mount.floorFrames == 300);
  CHECK(back.mount.floorSpreadRad == k.mount.floorSpreadRad);
  CHECK(back.mount.fromFloor);
  CHECK(back.timeOffset.offsetS == 0.045);
  CHECK(back.timeOffset.learnt);
  CHECK(back.timeOffset.frames == 288);
  REQUIRE(back.mountUp);
  CHECK(*back.mountUp == *k.mountUp);
  CHECK(sb::encodeKeptOdometry(back) == payload);

  // The next run's estimate starts as the kept one's, and corrects the wheels by it from its first step.
  sb::odometry::OdometryConfig config;
  sb::odometry::OdometryCalibration fresh(config), restored(config);
  restored.restore(back.calibration);
  const sb::odometry::CalibrationEstimate e = restored.estimate();
  CHECK(e.frames == 412);
  CHECK(e.scale == Approx(0.02 / 0.98).epsilon(1e-9));
  CHECK(fresh.estimate().scale == 0.0);
  sb::odometry::OdometryStep step;
  step.delta.translation() = Eigen::Vector3d(0, 0, 1.0);
  step.up = Eigen::Vector3d(0, -1, 0);
  step.dt = 0.1;
  CHECK(fresh.correct(step).delta.translation().z() == 1.0);
  CHECK(restored.correct(step).delta.translation().z() == Approx(0.98));
  sb::odometry::MountCalibration mount;
  mount.restore(back.mount);
  CHECK(mount.errorDeg() == Approx(1.5));
  CHECK(mount.turnSeenDeg() == Approx(4.2 * 180.0 / M_PI));

  std::vector<uint8_t> shorter = payload;
  shorter.pop_back();
  CHECK(refusal([&] { sb::decodeKeptOdometry(shorter, "S/odometry.bin", 2); }).find("'S/odometry.bin'") != std::string::npos);
  sb::KeptOdometry bad = k;
  bad.calibration.scaleInfo = -1.0;
  CHECK(refusal([&] { sb::decodeKeptOdometry(sb::encodeKeptOdometry(bad), "S/odometry.bin", 2); })
            .find("'S/odometry.bin' holds a calibration that is not one") != std::string::npos);
  bad = k;
  bad.mount.correction(0, 0) = 2.0;  // not a rotation
  CHECK(refusal([&] { sb::decodeKeptOdometry(sb::encodeKeptOdometry(bad), "S/odometry.bin", 2); }) != "");
  bad = k;
  bad.calibration.yawVec.x() = NAN;
  CHECK(refusal([&] { sb::decodeKeptOdometry(sb::encodeKeptOdometry(bad), "S/odometry.bin", 2); }) != "");
  bad = k;
  bad.timeOffset.offsetS = INFINITY;
  CHECK(refusal([&] { sb::decodeKeptOdometry(sb::encodeKeptOdometry(bad), "S/odometry.bin", 2); }) != "");
  bad = k;
  bad.mountUp = Eigen::Vector3d(0.0, -2.0, 0.0);  // not a direction
  CHECK(refusal([&] { sb::decodeKeptOdometry(sb::encodeKeptOdometry(bad), "S/odometry.bin", 2); }) != "");
  bad = k;
  bad.mountUp.reset();  // not recorded (a run whose odometry gave no pose)
  CHECK_FALSE(sb::decodeKeptOdometry(sb::encodeKeptOdometry(bad), "S/odometry.bin", 2).mountUp);

  // Version 1 (before the clock was kept): the same calibration and mount, no clock offset; a version this build
  // does not know is refused naming the file.
  const std::vector<uint8_t> v1(payload.begin(), payload.begin() + 268);
  const sb::KeptOdometry old = sb::decodeKeptOdometry(v1, "S/odometry.bin", 1);
  CHECK(old.calibration.frames == 412);
  CHECK(old.mount.correction == k.mount.correction);
  CHECK_FALSE(old.timeOffset.learnt);
  CHECK_FALSE(old.mountUp);  // not recorded: its correction is not restored (runtime/run_map_store.cpp)
  CHECK(refusal([&] { sb::decodeKeptOdometry(payload, "S/odometry.bin", 1); }).find("'S/odometry.bin'") !=
        std::string::npos);
  CHECK(refusal([&] { sb::decodeKeptOdometry(payload, "S/odometry.bin", 3); }).find("version 3") != std::string::npos);
}

namespace {

// The wheels' track of a turn that speeds up and slows down (a change of turn rate tells offsets apart), stamped
// `latencyS` late, and the view's frames (their true stamps, 30 a second) through it into `offset`.
void turnSeen(sb::odometry::TimeOffset& offset, double latencyS) {
  const auto yaw = [](double t) { return 0.6 * t - 0.25 * std::cos(2.0 * t); };
  sb::odometry::OdometryTrack track;
  for (double t = 0.0; t < 6.0; t += 0.01) {
    sb::odometry::OdometrySample s;
    s.timestamp = t + latencyS;
    s.T_camera_to_odom.linear() = Eigen::AngleAxisd(yaw(t), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    track.add(s);
  }
  for (int i = 1; i / 30.0 < 5.0; ++i)
    offset.add(track, (i - 1) / 30.0, i / 30.0, Eigen::Vector3d(0, 0, yaw(i / 30.0) - yaw((i - 1) / 30.0)));
}

}  // namespace

TEST_CASE("the odometry's clock offset kept by a run is the next run's start when its config takes it",
          "[map_store]") {
  sb::odometry::OdometryConfig config;
  config.timeOffsetRangeS = 0.2;  // learning on
  const sb::odometry::TimeOffset::State kept{0.045, true, 150};
  sb::odometry::TimeOffset restored(config);
  REQUIRE(restored.restore(kept));
  CHECK(restored.offset() == Approx(0.045).margin(0.0026));  // the offset tried nearest it (5 ms apart)
  CHECK(restored.learnt());
  // The evidence moves it from there as it would from the start value: the same latency keeps it, another
  // (none) takes it back.
  turnSeen(restored, 0.045);
  CHECK(restored.offset() == Approx(0.045).margin(0.006));
  sb::odometry::TimeOffset moved(config);
  REQUIRE(moved.restore(kept));
  turnSeen(moved, 0.0);
  CHECK(moved.offset() == Approx(0.0).margin(0.006));
  // Not taken: an offset never learnt, one outside this run's range, or a run whose offset is fixed.
  sb::odometry::TimeOffset fresh(config);
  CHECK_FALSE(fresh.restore({0.045, false, 0}));
  CHECK_FALSE(fresh.restore({0.35, true, 150}));
  CHECK(fresh.offset() == 0.0);
  CHECK_FALSE(fresh.learnt());
  sb::odometry::OdometryConfig fixed;
  fixed.timeOffsetS = 0.01;
  sb::odometry::TimeOffset fixedOffset(fixed);
  CHECK_FALSE(fixedOffset.restore(kept));
  CHECK(fixedOffset.offset() == 0.01);
}

TEST_CASE("a store's state files round-trip and a truncated, altered, foreign or other-version one is refused at "
          "open naming it", "[map_store]") {
  const std::string dir = sb::test::scratchDir("map_store_state");
  const std::string store = dir + "/store";
  fs::remove_all(store);
  const std::vector<uint8_t> wheels = sb::encodeKeptOdometry(learnt());
  const std::vector<uint8_t> votes = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  {
    sb::MapStore s(store, smallConfig());
    CHECK(s.keptState(sb::mapstore::kOdometryFile) == nullptr);
    s.saveState(sb::mapstore::kOdometryFile, wheels);
    s.saveState(sb::mapstore::kNavmapFile, votes);
    s.saveState(sb::mapstore::kNavmapFile, {});  // nothing to keep: the file stays as it was
    CHECK(s.summaryJson()["state_files_saved"]["odometry.bin"] == 316 + 28);
  }
  {
    sb::MapStore s(store, smallConfig());
    REQUIRE(s.keptState(sb::mapstore::kOdometryFile) != nullptr);
    CHECK(*s.keptState(sb::mapstore::kOdometryFile) == wheels);
    CHECK(s.keptStateVersion(sb::mapstore::kOdometryFile) == 2);
    CHECK(s.keptStateVersion(sb::mapstore::kNavmapFile) == 1);
    REQUIRE(s.keptState(sb::mapstore::kNavmapFile) != nullptr);
    CHECK(*s.keptState(sb::mapstore::kNavmapFile) == votes);
    CHECK(s.summaryJson()["state_files_kept"] == nlohmann::json({"navmap.bin", "odometry.bin"}));
  }
  const std::string file = store + "/navmap.bin";
  const std::vector<char> good = bytesOf(file);
  const auto refusedWith = [&](const std::vector<char>& bytes, const std::string& why) {
    writeBytes(file, bytes);
    const std::string message = refusal([&] { sb::MapStore s(store, smallConfig()); });
    INFO(message);
    CHECK(message.find("'" + file + "'") != std::string::npos);
    CHECK(message.find(why) != std::string::npos);
  };
  std::vector<char> bytes = good;
  bytes.resize(bytes.size() - 3);
  refusedWith(bytes, "truncated");
  bytes = good;
  bytes.back() ^= 0x10;
  refusedWith(bytes, "checksum");
  bytes = good;
  bytes[3] = 'X';
  refusedWith(bytes, "is not a map store navigation map");
  bytes = good;
  bytes[8] = 7;  // the version's low byte
  refusedWith(bytes, "format version 7");
  refusedWith(std::vector<char>(good.begin(), good.begin() + 10), "truncated");
  // odometry.bin with navmap.bin's magic: each file is read as what its name says.
  writeBytes(file, good);
  const std::vector<char> odometry = bytesOf(store + "/odometry.bin");
  writeBytes(store + "/odometry.bin", good);
  CHECK(refusal([&] { sb::MapStore s(store, smallConfig()); }).find("odometry.bin' is not a map store odometry") !=
        std::string::npos);
  writeBytes(store + "/odometry.bin", odometry);
  CHECK(refusal([&] { sb::MapStore s(store, smallConfig()); }) == "");
  // odometry.bin of version 1 (a store written before the clock offset was kept) opens as version 1; one of a
  // version after this build's is refused naming it.
  const auto asFile = [](const std::vector<uint8_t>& b) { return std::vector<char>(b.begin(), b.end()); };
  const std::vector<uint8_t> v1(wheels.begin(), wheels.begin() + 268);
  writeBytes(store + "/odometry.bin", asFile(sb::mapstore::encodeStateFile(sb::mapstore::kOdometryFile.magic, 1, v1)));
  {
    sb::MapStore s(store, smallConfig());
    CHECK(s.keptStateVersion(sb::mapstore::kOdometryFile) == 1);
    CHECK(sb::decodeKeptOdometry(*s.keptState(sb::mapstore::kOdometryFile), "o", 1).calibration.frames == 412);
  }
  writeBytes(store + "/odometry.bin", asFile(sb::mapstore::encodeStateFile(sb::mapstore::kOdometryFile.magic, 3, wheels)));
  const std::string newer = refusal([&] { sb::MapStore s(store, smallConfig()); });
  INFO(newer);
  CHECK(newer.find("odometry.bin' is format version 3, this build reads 1 to 2") != std::string::npos);
}
