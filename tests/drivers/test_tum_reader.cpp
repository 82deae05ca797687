#include <catch2/catch.hpp>
#include <filesystem>

#include "core/error.h"
#include "core/png_io.h"
#include "drivers/sequence.h"
#include "tests/drivers/fixtures.h"
#include "tests/support/test_data.h"

using namespace sb;
namespace fs = std::filesystem;

namespace {

SequenceOptions direct() {
  SequenceOptions o;
  o.prefetch = false;
  return o;
}

std::vector<DepthFrame> readAll(FrameSource& source) {
  std::vector<DepthFrame> frames;
  while (auto f = source.next()) frames.push_back(std::move(*f));
  return frames;
}

}  // namespace

TEST_CASE("TUM reader returns the written frames, timestamps and calibration", "[drivers][tum]") {
  const std::string dir =
      test::writePatternSequence(test::scratchDir("tum_basic") + "/seq", 4, test::smallInfo());
  auto source = openSequence(dir, direct());
  const SequenceInfo& info = source->info();
  CHECK(info.format == "tum");
  CHECK(info.path == dir);
  CHECK(info.frameCount == 4);
  CHECK(info.intrinsics.width == 6);
  CHECK(info.intrinsics.height == 4);
  CHECK(info.intrinsics.fx == 5.5f);
  CHECK(info.intrinsics.fy == 6.5f);
  CHECK(info.intrinsics.cx == 2.5f);
  CHECK(info.intrinsics.cy == 1.5f);
  CHECK(info.depthScale == 5000.0);
  CHECK(info.groundTruthPath.empty());
  CHECK_FALSE(info.volumeSize);

  const auto frames = readAll(*source);
  REQUIRE(frames.size() == 4);
  for (size_t i = 0; i < frames.size(); ++i) {
    CHECK(frames[i].index == i);
    CHECK(frames[i].timestamp == Approx(100.0 + 0.1 * i).margin(1e-9));
    CHECK(frames[i].depth.pixels() == test::patternDepth(i, 6, 4).pixels());
  }
  CHECK_FALSE(source->next());  // stays at the end
}

TEST_CASE("TUM reader: ground truth, volume hints, comments and CRLF lines", "[drivers][tum]") {
  const std::string dir = test::scratchDir("tum_misc") + "/seq";
  SequenceInfo written = test::smallInfo();
  written.volumeSize = 3.0;
  written.volumeInitialPosition = std::array<double, 3>{0.5, 0.5, 0.0};
  written.format = "synthetic";
  test::writePatternSequence(dir, 2, written);
  test::writeText(dir + "/groundtruth.txt", "# none\n");
  test::writeText(dir + "/depth.txt",
                  "# a comment\r\n\r\n  100.0 depth/000000.png\r\n# another\n100.5\tdepth/000001.png  \n");
  auto source = openSequence(dir, direct());
  CHECK(source->info().format == "synthetic");
  CHECK(source->info().groundTruthPath == dir + "/groundtruth.txt");
  REQUIRE(source->info().volumeSize);
  CHECK(*source->info().volumeSize == 3.0);
  REQUIRE(source->info().volumeInitialPosition);
  CHECK((*source->info().volumeInitialPosition)[2] == 0.0);
  const auto frames = readAll(*source);
  REQUIRE(frames.size() == 2);
  CHECK(frames[1].timestamp == 100.5);
  CHECK(frames[1].depth.pixels() == test::patternDepth(1, 6, 4).pixels());
}

TEST_CASE("TUM reader defaults without calibration.json, and options win over the file", "[drivers][tum]") {
  const std::string dir =
      test::writePatternSequence(test::scratchDir("tum_defaults") + "/seq", 2, test::smallInfo());
  fs::remove(dir + "/calibration.json");
  {
    auto source = openSequence(dir, direct());
    const SequenceInfo& info = source->info();
    CHECK(info.format == "tum");
    CHECK(info.intrinsics.fx == 525.f);
    CHECK(info.intrinsics.fy == 525.f);
    CHECK(info.intrinsics.cx == 319.5f);
    CHECK(info.intrinsics.cy == 239.5f);
    CHECK(info.depthScale == 5000.0);
    CHECK(info.intrinsics.width == 6);  // from the first PNG
    CHECK(info.intrinsics.height == 4);
  }
  test::writeText(dir + "/calibration.json",
                  R"({"width": 6, "height": 4, "fx": 10, "fy": 11, "cx": 3, "cy": 2, "depth_scale": 1000})");
  SequenceOptions o = direct();
  o.fx = 20.f;
  o.cy = 1.25f;
  o.depthScale = 2000.0;
  auto source = openSequence(dir, o);
  const SequenceInfo& info = source->info();
  CHECK(info.intrinsics.fx == 20.f);
  CHECK(info.intrinsics.fy == 11.f);
  CHECK(info.intrinsics.cx == 3.f);
  CHECK(info.intrinsics.cy == 1.25f);
  CHECK(info.depthScale == 2000.0);
}

TEST_CASE("TUM reader normalises invalid values to 0 and recognises 7-Scenes", "[drivers][tum]") {
  const std::string dir = test::scratchDir("tum_invalid") + "/seq";
  fs::create_directories(dir + "/depth");
  DepthRaw d(3, 2);
  d.pixels() = {0, 65535, 1234, 7, 65535, 4000};
  writePng16(dir + "/depth/a.png", d);
  test::writeText(dir + "/depth.txt", "0.0 depth/a.png\n");
  test::writeText(dir + "/calibration.json", R"({"invalid_depth_values": [0, 7, 65535]})");
  auto source = openSequence(dir, direct());
  CHECK(source->info().format == "7scenes");
  CHECK(source->info().depthScale == 1000.0);  // 7-Scenes default when the file gives none
  const auto frame = source->next();
  REQUIRE(frame);
  CHECK(frame->depth.pixels() == std::vector<uint16_t>{0, 0, 1234, 0, 0, 4000});

  // Without calibration, 65535 is still "no reading"; 7 is a valid value then.
  fs::remove(dir + "/calibration.json");
  auto plain = openSequence(dir, direct());
  CHECK(plain->info().format == "tum");
  CHECK(plain->next()->depth.pixels() == std::vector<uint16_t>{0, 0, 1234, 7, 0, 4000});
}

TEST_CASE("TUM reader: firstFrame and maxFrames select a range, keeping sequence indices", "[drivers][tum]") {
  const std::string dir =
      test::writePatternSequence(test::scratchDir("tum_range") + "/seq", 6, test::smallInfo());
  SequenceOptions o = direct();
  o.firstFrame = 2;
  o.maxFrames = 3;
  auto source = openSequence(dir, o);
  CHECK(source->info().frameCount == 3);
  const auto frames = readAll(*source);
  REQUIRE(frames.size() == 3);
  CHECK(frames[0].index == 2);
  CHECK(frames[2].index == 4);
  CHECK(frames[0].depth.pixels() == test::patternDepth(2, 6, 4).pixels());

  o.firstFrame = 5;
  o.maxFrames = 10;
  CHECK(openSequence(dir, o)->info().frameCount == 1);
  o.firstFrame = 6;
  CHECK_THROWS_WITH(openSequence(dir, o), Catch::Contains("first frame 6") && Catch::Contains("6 frames"));
}

TEST_CASE("TUM reader reports structural errors at open", "[drivers][tum][errors]") {
  const std::string root = test::scratchDir("tum_open_errors");
  const std::string dir = test::writePatternSequence(root + "/seq", 3, test::smallInfo());
  const std::string index = test::readText(dir + "/depth.txt");

  CHECK_THROWS_WITH(openSequence(root + "/nope", direct()),
                    Catch::Contains("nope") && Catch::Contains("not exist"));
  fs::create_directories(root + "/empty");
  CHECK_THROWS_WITH(openSequence(root + "/empty", direct()), Catch::Contains("depth.txt"));

  SECTION("non-monotonic timestamps name the line") {
    test::writeText(dir + "/depth.txt",
                    "# c\n1.0 depth/000000.png\n2.0 depth/000001.png\n2.0 depth/000002.png\n");
    CHECK_THROWS_WITH(openSequence(dir, direct()),
                      Catch::Contains("depth.txt' line 4") && Catch::Contains("does not increase"));
  }
  SECTION("malformed lines name the line") {
    test::writeText(dir + "/depth.txt", "1.0 depth/000000.png\n2.0\n");
    CHECK_THROWS_WITH(openSequence(dir, direct()),
                      Catch::Contains("line 2") && Catch::Contains("timestamp filename"));
    test::writeText(dir + "/depth.txt", "1.0 depth/000000.png extra\n");
    CHECK_THROWS_WITH(openSequence(dir, direct()), Catch::Contains("line 1"));
    test::writeText(dir + "/depth.txt", "1.0 depth/000000.png\n2.0x depth/000001.png\n");
    CHECK_THROWS_WITH(openSequence(dir, direct()), Catch::Contains("line 2") && Catch::Contains("2.0x"));
    test::writeText(dir + "/depth.txt", "nan depth/000000.png\n");
    CHECK_THROWS_WITH(openSequence(dir, direct()), Catch::Contains("line 1"));
  }
  SECTION("an index without frames") {
    test::writeText(dir + "/depth.txt", "# only a comment\n");
    CHECK_THROWS_WITH(openSequence(dir, direct()), Catch::Contains("no frames"));
  }
  SECTION("a missing PNG names the file, frame and line") {
    fs::remove(dir + "/depth/000002.png");
    CHECK_THROWS_WITH(openSequence(dir, direct()), Catch::Contains("000002.png") &&
                                                       Catch::Contains("frame 2") &&
                                                       Catch::Contains("line 4"));
  }
  SECTION("a malformed calibration.json names the key") {
    test::writeText(dir + "/calibration.json", R"({"fx": "big"})");
    CHECK_THROWS_WITH(openSequence(dir, direct()),
                      Catch::Contains("calibration.json") && Catch::Contains("'fx'"));
    test::writeText(dir + "/calibration.json", R"({"width": 0})");
    CHECK_THROWS_WITH(openSequence(dir, direct()), Catch::Contains("'width'"));
    test::writeText(dir + "/calibration.json", "{ not json");
    CHECK_THROWS_WITH(openSequence(dir, direct()),
                      Catch::Contains("not valid JSON") && Catch::Contains("line 1"));
  }
  SECTION("implausible intrinsics name the value, where it came from and the range") {
    // Issue 23: fx = 1e-300 passed the "positive" check and ran with 0 frames tracked; cx = 999999 too.
    test::writeText(dir + "/calibration.json", R"({"fx": 1e-300})");
    CHECK_THROWS_WITH(openSequence(dir, direct()), Catch::Contains("calibration.json") &&
                                                       Catch::Contains("'fx'") && Catch::Contains("1e-300"));
    test::writeText(dir + "/calibration.json", R"({"fx": 0.001})");
    CHECK_THROWS_WITH(openSequence(dir, direct()), Catch::Contains("fx = 0.001") &&
                                                       Catch::Contains("calibration.json") &&
                                                       Catch::Contains("not plausible"));
    test::writeText(dir + "/calibration.json", R"({"cx": 999999})");
    CHECK_THROWS_WITH(openSequence(dir, direct()),
                      Catch::Contains("cx = 999999") && Catch::Contains("not plausible"));
    fs::remove(dir + "/calibration.json");
    SequenceOptions o = direct();
    o.fy = 1e-20f;
    CHECK_THROWS_WITH(openSequence(dir, o), Catch::Contains("fy = 1e-20") && Catch::Contains("command line"));
  }
  SECTION("volume hints out of the pipeline's range name the file and the value as written") {
    // Issue 23: these failed later, in the pipeline config, naming neither the file nor the value.
    test::writeText(dir + "/calibration.json", R"({"volume_size_m": 1e-300})");
    CHECK_THROWS_WITH(openSequence(dir, direct()), Catch::Contains("calibration.json") &&
                                                       Catch::Contains("'volume_size_m'") &&
                                                       Catch::Contains("1e-300"));
    test::writeText(dir + "/calibration.json", R"({"volume_initial_position": [0.5, 7.25, 0.5]})");
    CHECK_THROWS_WITH(openSequence(dir, direct()), Catch::Contains("calibration.json") &&
                                                       Catch::Contains("'volume_initial_position'") &&
                                                       Catch::Contains("7.25"));
  }
  SECTION("a calibration.json that is a directory or deeply nested is named, not a crash") {
    fs::remove(dir + "/calibration.json");
    fs::create_directory(dir + "/calibration.json");
    CHECK_THROWS_WITH(openSequence(dir, direct()),
                      Catch::Contains("calibration.json") && Catch::Contains("is a directory"));
    fs::remove(dir + "/calibration.json");
    test::writeText(dir + "/calibration.json", "{\"fx\": " + std::string(70000, '['));
    CHECK_THROWS_WITH(openSequence(dir, direct()),
                      Catch::Contains("calibration.json") && Catch::Contains("deeper than"));
  }
  test::writeText(dir + "/depth.txt", index);
}

TEST_CASE("TUM reader reports bad frames at the frame", "[drivers][tum][errors]") {
  const std::string dir =
      test::writePatternSequence(test::scratchDir("tum_frame_errors") + "/seq", 4, test::smallInfo());
  const std::string png1 = dir + "/depth/000001.png";

  SECTION("truncated PNG") {
    const std::string bytes = test::readText(png1);
    test::writeText(png1, bytes.substr(0, bytes.size() / 2));
  }
  SECTION("8-bit PNG") {
    writePng8(png1, Image<uint8_t>(6, 4, 9));
  }
  SECTION("wrong size") {
    writePng16(png1, test::patternDepth(1, 4, 6));
  }
  auto source = openSequence(dir, direct());
  REQUIRE(source->next());
  CHECK_THROWS_WITH(source->next(), Catch::Contains("000001.png") && Catch::Contains("frame 1"));
  // The bad frame is skipped if the caller goes on.
  const auto after = source->next();
  REQUIRE(after);
  CHECK(after->index == 2);
}

TEST_CASE("TUM reader checks a PNG's size before decoding it", "[drivers][tum][errors]") {
  const std::string dir =
      test::writePatternSequence(test::scratchDir("tum_huge") + "/seq", 2, test::smallInfo());
  // Patch frame 0's IHDR to claim 100000 x 100000 pixels (big-endian width and height at byte 16).
  const std::string png0 = dir + "/depth/000000.png";
  std::string bytes = test::readText(png0);
  const std::string huge("\x00\x01\x86\xa0\x00\x01\x86\xa0", 8);
  bytes.replace(16, 8, huge);
  test::writeText(png0, bytes);

  auto source = openSequence(dir, direct());  // size from calibration.json: no decoding at open
  CHECK_THROWS_WITH(source->next(),
                    Catch::Contains("100000x100000") && Catch::Contains("6x4") && Catch::Contains("frame 0"));
  fs::remove(dir + "/calibration.json");  // now the first frame is probed at open
  CHECK_THROWS_WITH(openSequence(dir, direct()),
                    Catch::Contains("100000x100000") && Catch::Contains("4096"));
  // The issue's case: a small file claiming 8192 x 8192 as the first frame of an uncalibrated sequence.
  bytes.replace(16, 8, std::string("\x00\x00\x20\x00\x00\x00\x20\x00", 8));
  test::writeText(png0, bytes);
  CHECK_THROWS_WITH(openSequence(dir, direct()), Catch::Contains("8192x8192") && Catch::Contains("4096"));
}

TEST_CASE("TUM reader: ICL-NUIM archives with associations.txt and a .freiburg ground truth",
          "[drivers][tum]") {
  const std::string dir = test::scratchDir("tum_iclnuim");
  fs::create_directories(dir + "/depth");
  for (size_t i = 0; i < 3; ++i)
    writePng16(dir + "/depth/" + std::to_string(i) + ".png", test::patternDepth(i, 4, 3));
  test::writeText(dir + "/livingRoom0n.gt.freiburg", "0 0 0 0 0 0 0 1\n");
  SECTION("depth pair first") {
    test::writeText(dir + "/associations.txt",
                    "0 depth/0.png 0 rgb/0.png\n1 depth/1.png 1 rgb/1.png\n"
                    "2 depth/2.png 2 rgb/2.png\n");
  }
  SECTION("rgb pair first") {
    test::writeText(dir + "/associations.txt",
                    "0 rgb/0.png 0 depth/0.png\n1 rgb/1.png 1 depth/1.png\n"
                    "2 rgb/2.png 2 depth/2.png\n");
  }
  auto source = openSequence(dir, direct());
  const SequenceInfo& info = source->info();
  CHECK(info.format == "icl-nuim");
  CHECK(info.groundTruthPath == dir + "/livingRoom0n.gt.freiburg");
  CHECK(info.intrinsics.fx == 481.2f);
  CHECK(info.intrinsics.fy == 480.f);
  CHECK(info.depthScale == 5000.0);
  CHECK(info.frameCount == 3);
  const auto frames = readAll(*source);
  REQUIRE(frames.size() == 3);
  CHECK(frames[2].timestamp == 2.0);
  CHECK(frames[2].depth.pixels() == test::patternDepth(2, 4, 3).pixels());

  test::writeText(dir + "/associations.txt", "0 rgb/0.png 0 other/0.png\n");
  CHECK_THROWS_WITH(openSequence(dir, direct()),
                    Catch::Contains("associations.txt' line 1") && Catch::Contains("depth/"));
}

TEST_CASE("openSequence rejects impossible command-line values", "[drivers][errors]") {
  const std::string dir =
      test::writePatternSequence(test::scratchDir("bad_options") + "/seq", 1, test::smallInfo());
  SequenceOptions o = direct();
  o.depthScale = 0.0;
  CHECK_THROWS_WITH(openSequence(dir, o), Catch::Contains("depth scale"));
  o = direct();
  o.fx = -1.f;
  CHECK_THROWS_WITH(openSequence(dir, o), Catch::Contains("focal"));
  o = direct();
  o.height = 0;
  CHECK_THROWS_WITH(openSequence(dir, o), Catch::Contains("image sides"));
  o = direct();
  o.width = 8;  // the frames are 6 wide
  auto source = openSequence(dir, o);
  CHECK_THROWS_WITH(source->next(), Catch::Contains("6x4") && Catch::Contains("8x4"));
}
