#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <zlib.h>

#include "core/error.h"
#include "core/png_io.h"
#include "core/trajectory.h"
#include "tests/support/test_data.h"

using namespace sb;

TEST_CASE("png16 round-trips every value and rejects wrong formats", "[core][png]") {
  const std::string dir = test::scratchDir("png16");
  Image<uint16_t> img(37, 11);
  for (size_t i = 0; i < img.size(); ++i) img.data()[i] = static_cast<uint16_t>(i * 1777u);
  writePng16(dir + "/a.png", img);
  const auto back = readPng16(dir + "/a.png");
  REQUIRE(back.width() == 37);
  REQUIRE(back.height() == 11);
  CHECK(back.pixels() == img.pixels());

  Image<uint8_t> gray8(4, 4, 7);
  writePng8(dir + "/b.png", gray8);
  CHECK_THROWS_WITH(readPng16(dir + "/b.png"), Catch::Contains("8-bit grayscale") && Catch::Contains("b.png"));
  CHECK_THROWS_WITH(readPng16(dir + "/missing.png"), Catch::Contains("missing.png"));

  // Truncated file: first half of a valid PNG.
  {
    std::ifstream in(dir + "/a.png", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream out(dir + "/t.png", std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
  }
  CHECK_THROWS_WITH(readPng16(dir + "/t.png"), Catch::Contains("t.png"));
}

TEST_CASE("png16 refuses a header that claims a huge image before allocating", "[core][png]") {
  const std::string dir = test::scratchDir("png16_huge");
  writePng16(dir + "/a.png", Image<uint16_t>(6, 4, 100));
  std::ifstream in(dir + "/a.png", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  // IHDR data starts at byte 16 (width, height big-endian); its CRC covers type + 13 data bytes (12..28).
  const std::string huge("\x00\x01\x86\xa0\x00\x01\x86\xa0", 8);  // 100000 x 100000
  bytes.replace(16, 8, huge);
  const uLong crc = crc32(0L, reinterpret_cast<const Bytef*>(bytes.data() + 12), 17);
  for (int i = 0; i < 4; ++i) bytes[29 + i] = static_cast<char>((crc >> (24 - 8 * i)) & 0xff);
  std::ofstream(dir + "/huge.png", std::ios::binary) << bytes;
  CHECK_THROWS_WITH(readPng16(dir + "/huge.png"), Catch::Contains("100000x100000") && Catch::Contains("huge.png"));
}

TEST_CASE("TUM trajectories round-trip and bad lines are named", "[core][trajectory]") {
  const std::string dir = test::scratchDir("tum");
  Trajectory t;
  for (int i = 0; i < 5; ++i) {
    TimedPose p;
    p.timestamp = i / 30.0;
    p.T_camera_to_world = Eigen::Translation3d(0.1 * i, -0.2, 1.5) * Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d::UnitY());
    t.push_back(p);
  }
  writeTumTrajectory(dir + "/t.txt", t, "made by a test");
  {
    std::ifstream in(dir + "/t.txt");
    std::string l1, l2;
    std::getline(in, l1);
    std::getline(in, l2);
    CHECK(l1 == "# timestamp tx ty tz qx qy qz qw (camera-to-world, metres)");
    CHECK(l2 == "# made by a test");
  }
  const auto back = readTumTrajectory(dir + "/t.txt");
  REQUIRE(back.size() == t.size());
  for (size_t i = 0; i < t.size(); ++i) {
    CHECK(back[i].timestamp == Approx(t[i].timestamp).margin(1e-6));
    CHECK((back[i].T_camera_to_world.matrix() - t[i].T_camera_to_world.matrix()).norm() < 1e-8);
  }
  {
    std::ofstream bad(dir + "/bad.txt");
    bad << "# c\n0 0 0 0 0 0 0 1\n0.1 1 2 3 0 0\n";
  }
  CHECK_THROWS_WITH(readTumTrajectory(dir + "/bad.txt"), Catch::Contains("bad.txt:3"));
  {
    std::ofstream bad(dir + "/order.txt");
    bad << "1 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n";
  }
  CHECK_THROWS_WITH(readTumTrajectory(dir + "/order.txt"), Catch::Contains("does not increase"));
}
