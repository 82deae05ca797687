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
