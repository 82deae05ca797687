#pragma once
// Opening recorded sequences: TUM RGB-D layout (also ICL-NUIM and 7-Scenes in TUM layout, and the project's
// synthetic sequences) and SLAMBench .raw files.

#include <memory>
#include <optional>
#include <string>

#include "drivers/frame_source.h"

namespace sb {

// Overrides from the command line; any value set here wins over calibration.json and format defaults.
struct SequenceOptions {
  std::optional<double> depthScale;  // raw units per metre
  std::optional<float> fx, fy, cx, cy;
  std::optional<int> width, height;  // only meaningful for formats that do not store the size
  size_t maxFrames = 0;              // 0 = all frames
  size_t firstFrame = 0;             // skip this many frames at the start
  bool prefetch = true;              // decode ahead on a worker thread
  size_t prefetchDepth = 8;          // frames decoded ahead
};

// Opens `path`: a directory in TUM layout (depth.txt) or a `.raw` file. Reads the sequence index eagerly
// so that structural problems (missing files, non-monotonic timestamps, a .raw whose size is not a whole
// number of frames) are reported here, before any frame is processed. Throws sb::Error.
std::unique_ptr<FrameSource> openSequence(const std::string& path, const SequenceOptions& options = {});

}  // namespace sb
