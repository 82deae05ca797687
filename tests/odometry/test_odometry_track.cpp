// OdometryTrack (odometry/odometry_track.h): the one stream every odometry input fills.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "odometry/odometry_track.h"

using namespace sb::odometry;

namespace {

OdometrySample sample(double t, double x, double yawRad) {
  OdometrySample s;
  s.timestamp = t;
  s.T_camera_to_odom = Eigen::Translation3d(x, 0.0, 0.0) * Eigen::AngleAxisd(yawRad, Eigen::Vector3d::UnitY());
  return s;
}

}  // namespace

TEST_CASE("odometry is interpolated at a frame's stamp, never across a gap or far past its newest sample",
          "[odometry]") {
  OdometryTrackParams params;
  params.maxGapS = 0.1;
  params.maxExtrapolationS = 0.05;
  OdometryTrack track(params);
  CHECK_FALSE(track.poseAt(0.0));  // empty
  REQUIRE(track.add(sample(1.00, 0.0, 0.0)));
  REQUIRE(track.add(sample(1.02, 0.02, 0.02)));
  REQUIRE(track.add(sample(1.04, 0.04, 0.04)));

  // Between samples: position linear, rotation slerp.
  const auto mid = track.poseAt(1.03);
  REQUIRE(mid);
  CHECK(mid->translation().x() == Approx(0.03));
  CHECK(Eigen::AngleAxisd(mid->linear()).angle() == Approx(0.03));
  // Exactly on a sample.
  CHECK(track.poseAt(1.02)->translation().x() == Approx(0.02));
  // Before the first sample: nothing.
  CHECK_FALSE(track.poseAt(0.99));
  // Past the newest by at most the bound: extrapolated with the newest motion; farther: nothing.
  const auto ahead = track.poseAt(1.06);
  REQUIRE(ahead);
  CHECK(ahead->translation().x() == Approx(0.06));
  CHECK_FALSE(track.poseAt(1.10));
  // Other bounds (the run's config) for the same track.
  CHECK(track.poseAt(1.10, 0.1, 0.1));

  // A gap longer than maxGapS: no interpolation inside it.
  REQUIRE(track.add(sample(1.50, 0.5, 0.0)));
  CHECK_FALSE(track.poseAt(1.30));
  CHECK(track.poseAt(1.50));
}

TEST_CASE("odometry samples out of order or not finite are refused with the stamp named", "[odometry]") {
  OdometryTrack track;
  std::string why;
  REQUIRE(track.add(sample(2.0, 0.0, 0.0), &why));
  CHECK_FALSE(track.add(sample(2.0, 0.1, 0.0), &why));
  CHECK_THAT(why, Catch::Contains("2.000000") && Catch::Contains("must increase"));
  CHECK_FALSE(track.add(sample(NAN, 0.1, 0.0), &why));
  CHECK_FALSE(track.add(sample(3.0, INFINITY, 0.0), &why));
  CHECK_THAT(why, Catch::Contains("not finite"));
  CHECK(track.size() == 1);
}

TEST_CASE("the track keeps its capacity, the oldest samples going first", "[odometry]") {
  OdometryTrackParams params;
  params.capacity = 3;
  OdometryTrack track(params);
  for (int i = 0; i < 5; ++i) REQUIRE(track.add(sample(i * 0.02, i * 0.01, 0.0)));
  CHECK(track.size() == 3);
  CHECK_FALSE(track.poseAt(0.01));
  CHECK(track.poseAt(0.05));
  CHECK(*track.newestStamp() == Approx(0.08));
}

TEST_CASE("odometry.txt is read as TUM lines; a bad line is named", "[odometry]") {
  const auto dir = std::filesystem::temp_directory_path() / "sb-odometry-track-test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "odometry.txt").string();
  {
    std::ofstream out(path);
    out << "# timestamp tx ty tz qx qy qz qw\n";
    for (int i = 0; i < 5000; ++i) out << 10.0 + i * 0.02 << " " << i * 0.01 << " 0 0 0 0 0 1\n";
  }
  const OdometryTrack track = readOdometryFile(path);
  CHECK(track.size() == 5000);  // the whole file, past the default capacity
  CHECK(track.poseAt(10.01)->translation().x() == Approx(0.005));
  {
    std::ofstream out(path);
    out << "1.0 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n";
  }
  CHECK_THROWS_WITH(readOdometryFile(path), Catch::Contains("odometry.txt"));
  std::filesystem::remove_all(dir);
}

// Issue 53, finding 1: one ?ODOM sample stamped 9.9e9 s (inside the old [0, 1e10]) stood as the newest and every
// later sample of the robot was refused for the rest of the run.
TEST_CASE("one absurd stamp is refused alone: the next sane sample is taken", "[odometry][issue53]") {
  OdometryTrack track;
  for (int i = 0; i < 10; ++i) REQUIRE(track.add(sample(100.0 + 0.1 * i, 0.01 * i, 0.0)));
  std::string why;
  CHECK_FALSE(track.add(sample(9.9e9, 0.0, 0.0), &why));
  CHECK_THAT(why, Catch::Contains("9900000000.000000") && Catch::Contains("held"));
  CHECK(*track.newestStamp() == Approx(100.9));
  for (int i = 10; i < 20; ++i) CHECK(track.add(sample(100.0 + 0.1 * i, 0.01 * i, 0.0), &why));
  CHECK(track.size() == 20);
  CHECK(track.poseAt(101.85));
  // A stamp far back (0.5 s: a restarted robot's clock) alone is refused too, and the newest stays.
  CHECK_FALSE(track.add(sample(0.5, 0.0, 0.0), &why));
  CHECK_THAT(why, Catch::Contains("0.500000"));
  CHECK(track.add(sample(102.0, 0.2, 0.0)));
}

TEST_CASE("a new clock is taken once samples in a row confirm it, ahead or back", "[odometry][issue53]") {
  OdometryTrack track;
  for (int i = 0; i < 5; ++i) REQUIRE(track.add(sample(100.0 + 0.1 * i, 0.0, 0.0)));
  std::string why;
  // The robot's clock jumps 1000 s ahead: held, then taken at the third sample.
  CHECK_FALSE(track.add(sample(1100.0, 0.0, 0.0), &why));
  CHECK_FALSE(track.add(sample(1100.1, 0.0, 0.0), &why));
  CHECK_THAT(why, Catch::Contains("1 more"));
  CHECK(track.add(sample(1100.2, 0.0, 0.0), &why));
  CHECK(*track.newestStamp() == Approx(1100.2));
  CHECK(track.poseAt(1100.05));
  CHECK(track.add(sample(1100.3, 0.0, 0.0)));
  // And back (a bag replayed again): the samples after the new clock's first are dropped.
  CHECK_FALSE(track.add(sample(100.0, 0.0, 0.0)));
  CHECK_FALSE(track.add(sample(100.1, 0.0, 0.0)));
  CHECK(track.add(sample(100.2, 0.0, 0.0)));
  CHECK(*track.newestStamp() == Approx(100.2));
  CHECK(track.poseAt(100.15));
  // A first absurd sample (no frame known yet) is undone the same way by the sane clock.
  OdometryTrack first;
  REQUIRE(first.add(sample(4e9, 0.0, 0.0)));
  CHECK_FALSE(first.add(sample(10.0, 0.0, 0.0)));
  CHECK_FALSE(first.add(sample(10.1, 0.0, 0.0)));
  CHECK(first.add(sample(10.2, 0.0, 0.0)));
  CHECK(*first.newestStamp() == Approx(10.2));
  CHECK(first.size() == 3);
}

TEST_CASE("the frames' clock places the first sample and a sample after a pause", "[odometry][issue53]") {
  OdometryTrack track;
  track.noteFrameStamp(50.0);
  std::string why;
  CHECK_FALSE(track.add(sample(4e9, 0.0, 0.0), &why));  // the first sample, 4e9 s past the frames
  CHECK_THAT(why, Catch::Contains("4000000000.000000") && Catch::Contains("newest frame (50.000000 s)"));
  CHECK(track.add(sample(50.1, 0.0, 0.0), &why));
  CHECK(track.size() == 1);
  // The odometry paused 30 s while the frames went on: its next sample fits the frames' clock.
  track.noteFrameStamp(80.0);
  CHECK(track.add(sample(80.2, 0.0, 0.0), &why));
}

// Issue 53, finding 2: readOdometryFile held the whole file (about 920 B a sample; 10^7 lines exhausted memory).
TEST_CASE("an odometry.txt longer than the window is read as the frames need it", "[odometry][issue53]") {
  const auto dir = std::filesystem::temp_directory_path() / "sb-odometry-track-window";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "odometry.txt").string();
  const int n = 100000;
  {
    std::ofstream out(path);
    for (int i = 0; i < n; ++i) out << 10.0 + i * 0.01 << " " << i * 0.001 << " 0 0 0 0 0 1\n";
  }
  OdometryTrack track = readOdometryFile(path);
  CHECK(track.size() <= 16384);
  CHECK(track.poseAt(10.005)->translation().x() == Approx(0.0005));
  for (double t = 10.0; t < 10.0 + n * 0.01; t += 7.3) {  // the frames' stamps, in order, through the file
    const auto p = track.poseAt(t);
    REQUIRE(p);
    CHECK(p->translation().x() == Approx((t - 10.0) * 0.1).margin(1e-6));
    CHECK(track.size() <= 16384);
  }
  CHECK(track.poseAt(10.0 + (n - 1) * 0.01));  // the file's last sample
  CHECK(*track.newestStamp() == Approx(10.0 + (n - 1) * 0.01));
  CHECK(track.size() <= 16384);
  // A bad line far into the file is named before any sample is used.
  {
    std::ofstream out(path, std::ios::app);
    out << "2000.0 0 0 0 0 0 0\n";
  }
  CHECK_THROWS_WITH(readOdometryFile(path), Catch::Contains("odometry.txt:100001"));
  std::filesystem::remove_all(dir);
}
