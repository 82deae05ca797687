#pragma once
// calibration.json beside a sequence: image size, pinhole intrinsics, depth scale and optional hints.
// Keys (all optional when reading, each checked for type and range):
//   width, height (pixels), fx, fy, cx, cy (pixels), depth_scale (raw units per metre),
//   invalid_depth_values (array of raw values meaning "no reading", e.g. [0, 65535] for 7-Scenes),
//   volume_size_m (metres), volume_initial_position ([x, y, z] fractions of the volume side),
//   format (free text that becomes SequenceInfo::format, e.g. "icl-nuim", "synthetic").
// Unknown keys (sensor, frame_rate_hz, ...) are ignored.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "drivers/frame_source.h"
#include "drivers/sequence.h"

namespace sb {

struct Calibration {
  std::string path;  // the file it was read from
  std::optional<int> width, height;
  std::optional<float> fx, fy, cx, cy;
  std::optional<double> depthScale;
  std::vector<uint16_t> invalidDepthValues;
  std::string format;  // empty when absent
  std::optional<double> volumeSize;
  std::optional<std::array<double, 3>> volumeInitialPosition;
};

// What a format assumes when neither calibration.json nor the command line says otherwise.
struct CameraDefaults {
  std::string name;       // e.g. "TUM RGB-D (fx=fy=525, cx=319.5, cy=239.5, 5000 units/m)", for the warning
  Intrinsics intrinsics;  // width/height are ignored (the image size is resolved separately)
  double depthScale = 1000.0;  // raw units per metre
};

// Fills info.intrinsics (fx, fy, cx, cy) and info.depthScale with the precedence options > calibration >
// defaults, and the volume hints from the calibration. Logs one warning listing the values that came from
// the defaults (none when the calibration or the options gave them all).
void resolveCamera(SequenceInfo& info, const Calibration* calibration, const SequenceOptions& options,
                   const CameraDefaults& defaults);

// Once info.intrinsics has its image size: throws sb::Error when an intrinsic given by `options` or
// `calibration` is implausible for it (focal lengths outside [side/100, side*100] pixels, side = the longer
// image side; a principal point more than one image size outside the image), naming the value, where it
// came from and the range. Defaults are not checked.
void checkIntrinsics(const SequenceInfo& info, const Calibration* calibration,
                     const SequenceOptions& options);

// The raw values that mean "no reading": always 0 and 65535 (a saturated or missing sample in every supported
// format), plus the calibration's `invalid_depth_values`.
std::vector<uint16_t> invalidDepthValues(const Calibration* calibration);

// Replaces every invalid value in `depth` by 0.
void normaliseInvalidDepth(DepthRaw& depth, const std::vector<uint16_t>& invalidValues);

// Reads and validates a calibration.json. Throws sb::Error naming the file and key.
Calibration readCalibration(const std::string& path);

// Writes calibration.json from a sequence's info (size, intrinsics, depth scale, volume hints, and the format
// as key `format` when it is set, so that e.g. synthetic sequences re-read as "synthetic").
// Throws sb::Error if the file cannot be written.
void writeCalibration(const std::string& path, const SequenceInfo& info);

}  // namespace sb
