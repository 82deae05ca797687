#pragma once
// Writes a sequence in TUM RGB-D layout: depth/NNNNNN.png (16-bit), depth.txt (`timestamp depth/NNNNNN.png`),
// calibration.json (width, height, fx, fy, cx, cy, depth_scale, optional volume hints) and, when given,
// groundtruth.txt. Used by `slambooster synth` and by recording from a camera. The result re-reads through
// sb::openSequence.

#include <fstream>
#include <string>

#include "core/trajectory.h"
#include "drivers/frame_source.h"

namespace sb {

class TumSequenceWriter {
 public:
  // Creates `directory` (and depth/ inside it); throws sb::Error if it exists and is not empty, unless
  // `overwrite` is set. `info` gives intrinsics, depthScale and the optional volume hints.
  TumSequenceWriter(const std::string& directory, const SequenceInfo& info, bool overwrite = false);
  ~TumSequenceWriter();  // finishes if finish() was not called (errors are logged, not thrown)
  TumSequenceWriter(const TumSequenceWriter&) = delete;
  TumSequenceWriter& operator=(const TumSequenceWriter&) = delete;

  // Appends one frame (PNG written immediately, depth.txt line appended). Timestamps must increase.
  void write(const DepthFrame& frame);
  // Writes groundtruth.txt.
  void writeGroundTruth(const Trajectory& trajectory);
  // Flushes depth.txt and writes calibration.json. Throws sb::Error on I/O failure.
  void finish();

  const std::string& directory() const { return directory_; }

 private:
  std::string directory_;
  SequenceInfo info_;
  std::ofstream index_;
  double lastTimestamp_ = -1e300;
  size_t frames_ = 0;
  bool finished_ = false;
};

}  // namespace sb
