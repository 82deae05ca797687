#pragma once
// The CPU backend's track and reduce, four pixels of a row at a time (SSE2 on x86-64, NEON on armhf, plain
// C++ elsewhere). Per pixel, track makes the same float operations in the same order as kernels/track.h's
// track(), so every pixel gets the same correspondence, residual and Jacobian (armhf: NEON flushes denormals
// to zero); reduce sums them lane-wise, so the sums differ from reduce()'s in rounding only, and the counts
// are exact. kernels/track.h stays the reference (the OpenCL backend runs it unchanged).

#include <vector>

#include "kernels/common.h"
#include "pipeline/backend.h"
#include "pipeline/pair_noise.h"

namespace sb {

// One track + reduce pass: the input level's maps (camera frame) and the reference maps (world frame), 3
// floats per pixel, row-major, with the transforms and thresholds of kernels/track.h's track().
struct TrackInputs {
  const float* vertex = nullptr;  // input level, width x height
  const float* normal = nullptr;
  int width = 0, height = 0;
  const float* refVertex = nullptr;  // reference maps, refWidth x refHeight
  const float* refNormal = nullptr;
  int refWidth = 0, refHeight = 0;
  SbMat34 cameraToWorld{};
  SbMat34 worldToRefPixel{};       // K * inverse(reference pose)
  float distanceThreshold = 0.0f;  // metres
  float normalThreshold = 0.0f;    // cosine of the largest angle between the normals
};

// track's output for a band of rows, structure of arrays: per row, kTrackTerms arrays of `stride` floats (the
// residual, then the 6 Jacobian entries; 0 for every pixel that is no inlier and for the padding up to
// `stride`), followed by the band's counts. Scratch that keeps its memory between bands.
struct TrackBand {
  static constexpr int kTrackTerms = 7;
  int rows = 0;
  int stride = 0;             // floats per array: the width rounded up to 4
  std::vector<float> values;  // rows x kTrackTerms x stride
  int inliers = 0;            // SB_TRACK_INLIER
  int tooFar = 0;             // SB_TRACK_TOO_FAR
  int badNormal = 0;          // SB_TRACK_BAD_NORMAL
  int noCorrespondence = 0;   // SB_TRACK_OUTSIDE or SB_TRACK_NO_REFERENCE
};

// track for rows [y0, y1) of the input level into `band`.
void trackBand(const TrackInputs& in, int y0, int y1, TrackBand& band);

// reduce: adds `band` to `sums` (the SB_REDUCE_SIZE layout of kernels/track.h). Each row is summed in float,
// four lanes (pixels x = 0, 1, 2, 3 mod 4) apart, and the lanes are added in double in a fixed order: the
// result depends on the band's rows only.
void reduceBand(const TrackBand& band, TrackSums& sums);

// The blocks of `block` x `block` pixels of `band` (image `width` pixels wide; blocks start at the band's
// first row) as kernels/track.h's trackBlock rows, reduced: adds their reduce() sums (in float per band,
// blocks in row-major order) to `sums`. The same blocks, in the same order, as trackBlock over the image
// when the band starts at a multiple of `block`.
void reduceBandBlocks(const TrackBand& band, int width, int block, TrackSums& sums);

// The largest float s with sqrtf(s) <= distance: sqrtf(s) > distance exactly when s > this (for s >= 0), so
// track() can compare squared lengths without a square root and reject the same pairs.
float squaredDistanceLimit(float distance);

// The pairs of a track pass tested with tolerances widened to the sensor's noise at each input pixel's depth
// (pipeline/pair_noise.h), by the scalar kernel (kernels/track.h's track()); `levelFocalPx`: the input level's fx.
PairCounts countPairsInNoise(const TrackInputs& in, const DepthNoiseModel& model, double levelFocalPx);

}  // namespace sb
