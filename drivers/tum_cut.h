#pragma once
// Cutting a TUM-layout sequence by a frame list without copying its depth images: the cut's depth.txt
// points at the source's PNGs (absolute paths, which drivers/tum_reader.h accepts), with new timestamps that
// increase at the source's frame rate (its median frame interval) from the first listed frame's timestamp;
// groundtruth.txt holds the source's reference pose of each listed frame (nearest in time within
// maxTimeDifferenceS) at the new timestamp; calibration.json is the source's (written from its resolved
// camera when it has none); segments.csv names the ranges (`src-A-B`, frames of the cut [begin, end)).
// A frame list such as "0-299,100-199" makes a kidnap from real data: the camera jumps back to a place seen
// earlier, and only the frame list changed.

#include <cstddef>
#include <string>
#include <vector>

namespace sb {

// An inclusive range of source frame indices (positions in the source's depth.txt frame list).
struct FrameRange {
  size_t first = 0, last = 0;
};

// Parses "A-B,C,D-E" (inclusive, 0-based; a single number is one frame; spaces allowed around items).
// Throws sb::Error naming the item for malformed input, an empty list or a range whose end is before its
// start.
std::vector<FrameRange> parseFrameList(const std::string& text);

struct CutOptions {
  bool overwrite = false;            // replace the contents of a non-empty output directory
  double maxTimeDifferenceS = 0.02;  // a frame's reference pose is the nearest within this (TUM convention)
};

// Where two consecutive ranges meet: the motion between the last frame of one and the first of the next.
struct CutJump {
  size_t frame = 0;                              // first frame of the cut after the jump
  size_t fromSource = 0, toSource = 0;           // source frames either side
  double translationM = 0.0, rotationDeg = 0.0;  // from the reference poses; negative when either is missing
};

struct CutResult {
  size_t frames = 0;
  size_t groundTruthPoses = 0;  // listed frames with a reference pose (all, unless the source lacks some)
  double frameIntervalS = 0.0;  // of the source, seconds
  std::vector<CutJump> jumps;   // one per range boundary
};

// Writes the cut of `sourceDir` (a TUM-layout directory) into `outDir`. Throws sb::Error: a frame past the
// source's end, an unreadable source, a non-empty output directory (without overwrite), an output inside the
// source, a source with fewer than two frames (no frame rate).
CutResult cutTumSequence(const std::string& sourceDir, const std::vector<FrameRange>& ranges,
                         const std::string& outDir, const CutOptions& options = {});

}  // namespace sb
