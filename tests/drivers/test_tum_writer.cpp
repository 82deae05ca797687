#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"
#include "core/png_io.h"
#include "drivers/tum_writer.h"
#include "tests/support/test_data.h"

using namespace sb;
namespace fs = std::filesystem;

namespace {

SequenceInfo smallInfo() {
  SequenceInfo info;
  info.intrinsics = Intrinsics{6, 4, 5.5f, 6.5f, 2.5f, 1.5f};
  info.depthScale = 5000.0;
  return info;
}

DepthFrame makeFrame(size_t index, double timestamp, int width, int height) {
  DepthFrame f;
  f.index = index;
  f.timestamp = timestamp;
  f.depth = DepthRaw(width, height);
  for (size_t i = 0; i < f.depth.size(); ++i) f.depth.data()[i] = static_cast<uint16_t>(1000 * index + 7 * i);
  return f;
}

std::vector<std::string> dataLines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#') lines.push_back(line);
  return lines;
}

}  // namespace

TEST_CASE("TumSequenceWriter writes depth PNGs, depth.txt and calibration.json", "[drivers][writer]") {
  const std::string dir = test::scratchDir("writer_basic") + "/seq";
  SequenceInfo info = smallInfo();
  info.volumeSize = 4.5;
  info.volumeInitialPosition = std::array<double, 3>{0.5, 0.25, 0.125};
  {
    TumSequenceWriter writer(dir, info);
    for (size_t i = 0; i < 3; ++i) writer.write(makeFrame(i, 10.0 + 0.5 * i, 6, 4));
    Trajectory gt(2);
    gt[1].timestamp = 1.0;
    gt[1].T_camera_to_world.translation() = Eigen::Vector3d(1, 2, 3);
    writer.writeGroundTruth(gt);
    writer.finish();
  }
  for (size_t i = 0; i < 3; ++i) {
    const std::string png = dir + "/depth/00000" + std::to_string(i) + ".png";
    REQUIRE(fs::exists(png));
    CHECK(readPng16(png).pixels() == makeFrame(i, 0, 6, 4).depth.pixels());
  }
  const auto lines = dataLines(dir + "/depth.txt");
  REQUIRE(lines.size() == 3);
  CHECK(lines[0] == "10.000000 depth/000000.png");
  CHECK(lines[2] == "11.000000 depth/000002.png");

  std::ifstream calIn(dir + "/calibration.json");
  const auto cal = nlohmann::json::parse(calIn);
  CHECK(cal.at("width") == 6);
  CHECK(cal.at("height") == 4);
  CHECK(cal.at("fx").get<float>() == 5.5f);
  CHECK(cal.at("fy").get<float>() == 6.5f);
  CHECK(cal.at("cx").get<float>() == 2.5f);
  CHECK(cal.at("cy").get<float>() == 1.5f);
  CHECK(cal.at("depth_scale").get<double>() == 5000.0);
  CHECK(cal.at("volume_size_m").get<double>() == 4.5);
  CHECK(cal.at("volume_initial_position").get<std::vector<double>>() ==
        std::vector<double>{0.5, 0.25, 0.125});

  const auto gtLines = dataLines(dir + "/groundtruth.txt");
  REQUIRE(gtLines.size() == 2);
  std::istringstream second(gtLines[1]);
  double t = 0, x = 0, y = 0, z = 0;
  second >> t >> x >> y >> z;
  CHECK(t == 1.0);
  CHECK(x == 1.0);
  CHECK(y == 2.0);
  CHECK(z == 3.0);
}

TEST_CASE("TumSequenceWriter finishes in its destructor", "[drivers][writer]") {
  const std::string dir = test::scratchDir("writer_dtor") + "/seq";
  {
    TumSequenceWriter writer(dir, smallInfo());
    writer.write(makeFrame(0, 0.0, 6, 4));
  }
  CHECK(fs::exists(dir + "/calibration.json"));
  CHECK(dataLines(dir + "/depth.txt").size() == 1);
}

TEST_CASE("TumSequenceWriter rejects bad input", "[drivers][writer]") {
  const std::string root = test::scratchDir("writer_errors");
  const std::string dir = root + "/seq";
  TumSequenceWriter writer(dir, smallInfo());
  writer.write(makeFrame(0, 1.0, 6, 4));
  CHECK_THROWS_WITH(writer.write(makeFrame(1, 1.0, 6, 4)),
                    Catch::Contains("frame 1") && Catch::Contains("increase"));
  CHECK_THROWS_WITH(writer.write(makeFrame(1, 1.0000001, 6, 4)), Catch::Contains("increase"));
  CHECK_THROWS_WITH(writer.write(makeFrame(1, 2.0, 5, 4)), Catch::Contains("5x4") && Catch::Contains("6x4"));
  writer.write(makeFrame(1, 2.0, 6, 4));
  writer.finish();
  CHECK(dataLines(dir + "/depth.txt").size() == 2);

  // A non-empty directory is refused unless overwriting, which replaces the previous sequence only.
  CHECK_THROWS_WITH(TumSequenceWriter(dir, smallInfo()),
                    Catch::Contains("not empty") && Catch::Contains(dir));
  std::ofstream(dir + "/notes.txt") << "keep me\n";
  {
    TumSequenceWriter again(dir, smallInfo(), true);
    again.write(makeFrame(0, 0.0, 6, 4));
  }
  CHECK(dataLines(dir + "/depth.txt").size() == 1);
  CHECK_FALSE(fs::exists(dir + "/depth/000001.png"));
  CHECK(fs::exists(dir + "/notes.txt"));

  std::ofstream(root + "/file") << "x";
  CHECK_THROWS_WITH(TumSequenceWriter(root + "/file", smallInfo()), Catch::Contains("not a directory"));
}
