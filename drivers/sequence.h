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
  std::optional<int> width, height;  // expected image size, pixels; a frame of another size is an error
  size_t maxFrames = 0;              // 0 = all frames
  size_t firstFrame = 0;             // skip this many frames at the start (DepthFrame::index keeps counting
                                     // from the sequence's start, so frame 0 read is index firstFrame)
  bool prefetch = true;              // decode ahead on worker threads (drivers/prefetch_source.h)
  size_t prefetchDepth = 8;          // frames decoded ahead
  size_t prefetchThreads = 2;        // decoding threads for TUM-layout sequences (a .raw file uses one)
  std::string depthTopic;            // ROS bag: the sensor_msgs/Image depth topic; empty = the bag's only one
};

// Opens `path`: a directory in TUM layout (depth.txt; or the path of its depth.txt), a `.raw` file or a ROS
// `.bag` file (through the bag plugin, drivers/bag_loader.h: only where slambooster-ros is installed); see
// drivers/tum_reader.h and drivers/raw_reader.h for each format's calibration and defaults. Precedence for
// intrinsics and depth scale: options > calibration.json > format defaults (a warning lists the defaulted
// values). Every invalid depth value (0, 65535, calibration.json's `invalid_depth_values`) is returned as 0.
// Reads the sequence index eagerly so that structural problems (missing files, non-monotonic timestamps, a
// .raw whose size is not a whole number of frames) are reported here, before any frame is processed. Throws
// sb::Error.
std::unique_ptr<FrameSource> openSequence(const std::string& path, const SequenceOptions& options = {});

}  // namespace sb
