#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "drivers/raw_reader.h"
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

std::string writeRaw(const std::string& path, size_t frames, int width, int height) {
  std::ofstream out(path, std::ios::binary);
  for (size_t i = 0; i < frames; ++i) appendRawFrame(out, test::patternDepth(i, width, height));
  return path;
}

// Little-endian bytes of a uint32, for hand-made headers.
std::string le32(uint32_t v) {
  return std::string{static_cast<char>(v & 0xff), static_cast<char>((v >> 8) & 0xff),
                     static_cast<char>((v >> 16) & 0xff), static_cast<char>((v >> 24) & 0xff)};
}

}  // namespace

TEST_CASE(".raw round trip: pixels, 30 Hz timestamps, millimetres, ICL-NUIM default camera",
          "[drivers][raw]") {
  const std::string path = writeRaw(test::scratchDir("raw_basic") + "/seq.raw", 3, 5, 3);
  auto source = openSequence(path, direct());
  const SequenceInfo& info = source->info();
  CHECK(info.format == "raw");
  CHECK(info.frameCount == 3);
  CHECK(info.intrinsics.width == 5);
  CHECK(info.intrinsics.height == 3);
  CHECK(info.depthScale == 1000.0);
  CHECK(info.intrinsics.fx == 481.2f);
  CHECK(info.intrinsics.fy == 480.f);
  CHECK(info.intrinsics.cx == 319.5f);
  CHECK(info.intrinsics.cy == 239.5f);
  for (size_t i = 0; i < 3; ++i) {
    const auto frame = source->next();
    REQUIRE(frame);
    CHECK(frame->index == i);
    CHECK(frame->timestamp == Approx(i / 30.0));
    CHECK(frame->depth.pixels() == test::patternDepth(i, 5, 3).pixels());
  }
  CHECK_FALSE(source->next());
}

TEST_CASE(".raw: the byte layout is little-endian with an RGB block after the depth", "[drivers][raw]") {
  // Hand-written 2x1 frame: depth 0x0102 and 65535 (invalid -> 0), then a 2x1 RGB block.
  const std::string path = test::scratchDir("raw_bytes") + "/hand.raw";
  test::writeText(path, le32(2) + le32(1) + std::string("\x02\x01\xff\xff", 4) + le32(2) + le32(1) +
                            std::string(6, '\x7f'));
  auto source = openSequence(path, direct());
  const auto frame = source->next();
  REQUIRE(frame);
  CHECK(frame->depth.pixels() == std::vector<uint16_t>{0x0102, 0});
}

TEST_CASE(".raw: calibration precedence options > <file>.json > calibration.json", "[drivers][raw]") {
  const std::string dir = test::scratchDir("raw_calibration");
  const std::string path = writeRaw(dir + "/seq.raw", 2, 5, 3);
  test::writeText(dir + "/calibration.json",
                  R"({"fx": 100, "fy": 101, "cx": 2, "cy": 1, "depth_scale": 5000})");
  {
    auto source = openSequence(path, direct());
    CHECK(source->info().intrinsics.fx == 100.f);
    CHECK(source->info().depthScale == 5000.0);
  }
  test::writeText(path + ".json", R"({"fx": 200, "fy": 201, "cx": 2.5, "cy": 1.5, "format": "icl-nuim"})");
  SequenceOptions o = direct();
  o.fy = 7.f;
  auto source = openSequence(path, o);
  CHECK(source->info().format == "icl-nuim");
  CHECK(source->info().intrinsics.fx == 200.f);
  CHECK(source->info().intrinsics.fy == 7.f);
  CHECK(source->info().intrinsics.cx == 2.5f);
  CHECK(source->info().depthScale == 1000.0);  // <file>.json replaces calibration.json entirely

  test::writeText(path + ".json", R"({"width": 640, "height": 480})");
  CHECK_THROWS_WITH(openSequence(path, direct()), Catch::Contains("seq.raw.json") && Catch::Contains("5x3"));
}

TEST_CASE(".raw: firstFrame and maxFrames", "[drivers][raw]") {
  const std::string path = writeRaw(test::scratchDir("raw_range") + "/seq.raw", 5, 4, 2);
  SequenceOptions o = direct();
  o.firstFrame = 3;
  auto source = openSequence(path, o);
  CHECK(source->info().frameCount == 2);
  const auto frame = source->next();
  REQUIRE(frame);
  CHECK(frame->index == 3);
  CHECK(frame->timestamp == Approx(3 / 30.0));
  CHECK(frame->depth.pixels() == test::patternDepth(3, 4, 2).pixels());
  o.firstFrame = 5;
  CHECK_THROWS_WITH(openSequence(path, o), Catch::Contains("past its end"));
}

TEST_CASE(".raw structural errors", "[drivers][raw][errors]") {
  const std::string dir = test::scratchDir("raw_errors");
  const std::string path = writeRaw(dir + "/seq.raw", 3, 4, 2);
  const std::string whole = test::readText(path);

  SECTION("truncated file is reported at open with the frame") {
    test::writeText(path, whole.substr(0, whole.size() - 10));
    CHECK_THROWS_WITH(openSequence(path, direct()), Catch::Contains("seq.raw") &&
                                                        Catch::Contains("frame 2") &&
                                                        Catch::Contains("not a whole number"));
  }
  SECTION("empty file") {
    test::writeText(path, "");
    CHECK_THROWS_WITH(openSequence(path, direct()), Catch::Contains("seq.raw") && Catch::Contains("empty"));
  }
  SECTION("absurd header sizes do not allocate") {
    test::writeText(path, le32(1u << 30) + le32(1u << 30) + std::string(100, '\0'));
    CHECK_THROWS_WITH(openSequence(path, direct()), Catch::Contains("seq.raw") && Catch::Contains("frame 0"));
    test::writeText(path, le32(4) + le32(2) + std::string(16, '\0') + le32(0xffffffffu) + le32(3));
    CHECK_THROWS_WITH(openSequence(path, direct()), Catch::Contains("corrupt"));
  }
  SECTION("a frame whose size differs (same byte count) is reported at that frame") {
    std::string edited = whole;
    const size_t frameBytes = whole.size() / 3;
    edited.replace(frameBytes, 8, le32(2) + le32(4));  // frame 1 claims 2x4 instead of 4x2
    test::writeText(path, edited);
    auto source = openSequence(path, direct());
    REQUIRE(source->next());
    CHECK_THROWS_WITH(source->next(), Catch::Contains("seq.raw") && Catch::Contains("frame 1") &&
                                          Catch::Contains("2x4") && Catch::Contains("4x2"));
    const auto after = source->next();
    REQUIRE(after);
    CHECK(after->index == 2);
  }
  SECTION("command-line size contradicting the file") {
    SequenceOptions o = direct();
    o.width = 640;
    CHECK_THROWS_WITH(openSequence(path, o), Catch::Contains("640"));
  }
  SECTION("unknown file type") {
    test::writeText(dir + "/seq.bin", whole);
    CHECK_THROWS_WITH(openSequence(dir + "/seq.bin", direct()),
                      Catch::Contains("seq.bin") && Catch::Contains(".raw"));
  }
}

TEST_CASE(".raw through the prefetching worker gives the same frames", "[drivers][raw][prefetch]") {
  const std::string path = writeRaw(test::scratchDir("raw_prefetch") + "/seq.raw", 7, 4, 2);
  SequenceOptions ahead;
  ahead.prefetchDepth = 2;
  auto source = openSequence(path, ahead);
  for (size_t i = 0; i < 7; ++i) {
    const auto frame = source->next();
    REQUIRE(frame);
    CHECK(frame->index == i);
    CHECK(frame->depth.pixels() == test::patternDepth(i, 4, 2).pixels());
  }
  CHECK_FALSE(source->next());
}
