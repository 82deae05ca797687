#pragma once
// calibration.json beside a sequence: image size, pinhole intrinsics, depth scale and optional hints.
// Keys (all optional when reading, each checked for type and range):
//   width, height (pixels), fx, fy, cx, cy (pixels), depth_scale (raw units per metre),
//   invalid_depth_values (array of raw values meaning "no reading", e.g. [0, 65535] for 7-Scenes),
//   volume_size_m (metres), volume_initial_position ([x, y, z] fractions of the volume side).
// Unknown keys (sensor, frame_rate_hz, ...) are ignored.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "drivers/frame_source.h"

namespace sb {

struct Calibration {
  std::string path;  // the file it was read from
  std::optional<int> width, height;
  std::optional<float> fx, fy, cx, cy;
  std::optional<double> depthScale;
  std::vector<uint16_t> invalidDepthValues;
  std::optional<double> volumeSize;
  std::optional<std::array<double, 3>> volumeInitialPosition;
};

// Reads and validates a calibration.json. Throws sb::Error naming the file and key.
Calibration readCalibration(const std::string& path);

// Writes calibration.json from a sequence's info (size, intrinsics, depth scale, volume hints).
// Throws sb::Error if the file cannot be written.
void writeCalibration(const std::string& path, const SequenceInfo& info);

}  // namespace sb
