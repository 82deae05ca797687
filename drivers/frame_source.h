#pragma once
// The frame-source interface: anything that yields timestamped depth frames (a replayed sequence, a camera).
// Drivers know nothing of policy or transport; they return frames.

#include <cstddef>
#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "core/image.h"
#include "core/intrinsics.h"

namespace sb {

struct DepthFrame {
  size_t index = 0;        // 0-based position in the sequence / stream
  double timestamp = 0.0;  // seconds (sequence time for replay, CLOCK_MONOTONIC for live sources)
  DepthRaw depth;          // raw sensor units; every invalid reading (0, 65535, ...) is normalised to 0
};

struct SequenceInfo {
  std::string path;             // where it came from (directory, file or device URI)
  std::string format;           // "tum", "icl-nuim", "7scenes", "raw", "synthetic", "openni2", ...
  Intrinsics intrinsics;        // of the full-size depth image
  double depthScale = 1000.0;   // raw units per metre (1000 = millimetres, 5000 = TUM/ICL-NUIM)
  size_t frameCount = 0;        // 0 when unknown (live)
  std::string groundTruthPath;  // TUM trajectory of reference poses, empty when there is none
  // Optional reconstruction-volume hints a dataset may carry (calibration.json keys `volume_size_m` and
  // `volume_initial_position`): the cube's side in metres and the first camera position as fractions of it.
  std::optional<double> volumeSize;
  std::optional<std::array<double, 3>> volumeInitialPosition;
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual const SequenceInfo& info() const = 0;
  // The next frame, or nullopt at the end of the sequence. Throws sb::Error naming the file and frame on
  // bad input.
  virtual std::optional<DepthFrame> next() = 0;
};

}  // namespace sb
