#pragma once
// Small sequences written into scratch directories for the driver tests.

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "drivers/frame_source.h"
#include "drivers/tum_writer.h"

namespace sb::test {

// A known pattern: distinct per frame and pixel, never 0 or 65535.
inline uint16_t patternValue(size_t frame, size_t pixel) {
  return static_cast<uint16_t>(1 + (frame * 977 + pixel * 13) % 60000);
}

inline DepthRaw patternDepth(size_t frame, int width, int height) {
  DepthRaw d(width, height);
  for (size_t i = 0; i < d.size(); ++i) d.data()[i] = patternValue(frame, i);
  return d;
}

inline SequenceInfo smallInfo(int width = 6, int height = 4) {
  SequenceInfo info;
  info.intrinsics = Intrinsics{width, height, 5.5f, 6.5f, 2.5f, 1.5f};
  info.depthScale = 5000.0;
  return info;
}

// Writes `frames` pattern frames with timestamps 100 + 0.1 * i; returns the directory.
inline std::string writePatternSequence(const std::string& dir, size_t frames, const SequenceInfo& info) {
  TumSequenceWriter writer(dir, info);
  for (size_t i = 0; i < frames; ++i) {
    DepthFrame f;
    f.index = i;
    f.timestamp = 100.0 + 0.1 * static_cast<double>(i);
    f.depth = patternDepth(i, info.intrinsics.width, info.intrinsics.height);
    writer.write(f);
  }
  writer.finish();
  return dir;
}

inline void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

inline std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace sb::test
