#pragma once
// Replays a SLAMBench `.raw` file. Per frame, little-endian:
//   uint32 width, uint32 height, width*height uint16 depth (millimetres),
//   uint32 width, uint32 height, width*height*3 uint8 RGB (skipped).
// Every frame must have the first frame's sizes, so the file size must be a whole number of frames (checked
// at open). The format stores no timestamps: frame i gets i / 30 s (the 30 Hz of the Kinect recordings
// SLAMBench converts). Depth scale 1000 unless overridden.
// Intrinsics: options > `<file>.json` > `calibration.json` in the file's directory > the ICL-NUIM camera
// (fx = 481.2, fy = 480, cx = 319.5, cy = 239.5; the sequences SLAMBench ships as .raw), with a warning.
// SequenceInfo::format is "raw".

#include <cstdint>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "drivers/frame_source.h"
#include "drivers/sequence.h"

namespace sb {

// Writes one frame in the .raw layout (RGB written as zeros of the depth's size). For tests and converters.
void appendRawFrame(std::ostream& out, const DepthRaw& depth);

class RawReader : public FrameSource {
 public:
  // Opens the file and checks its structure. Throws sb::Error.
  RawReader(const std::string& path, const SequenceOptions& options);

  const SequenceInfo& info() const override { return info_; }
  std::optional<DepthFrame> next() override;

 private:
  [[noreturn]] void fail(size_t frame, const std::string& what) const;
  void readHeader(size_t frame, uint64_t offset, const char* what, uint32_t expectW, uint32_t expectH);

  SequenceInfo info_;
  std::ifstream file_;
  uint32_t width_ = 0, height_ = 0;        // depth image size, pixels
  uint32_t rgbWidth_ = 0, rgbHeight_ = 0;  // RGB image size, pixels
  uint64_t frameBytes_ = 0;
  size_t first_ = 0, end_ = 0, cursor_ = 0;  // frame range [first_, end_) in file order
  std::vector<std::uint8_t> buffer_;
  std::vector<uint16_t> invalidValues_;
};

}  // namespace sb
