#pragma once
// Random-fern codes of a depth frame, for recognising a place seen before (after Glocker, Shotton, Criminisi
// and Izadi, "Real-time RGB-D camera relocalization via randomized ferns for keyframe encoding", IEEE TVCG
// 2015; depth only here). The frame is shrunk to a small image of cells (the mean of a sparse grid of valid
// readings per cell) and normalised by subtracting its mean valid depth, so that the code describes the shape
// of the view rather than how far the camera stands. Each fern is a few binary tests "cell c is deeper than
// the mean by more than t metres" at random cells and thresholds; its code is the bits of its tests. Two views
// are alike when many ferns give the same code (FernCode::dissimilarity).
//
// Cost: cells x samples per cell reads of the raw frame plus ferns x tests comparisons, independent of the
// image size (defaults: 1200 cells x 16 samples, 500 x 4 tests).

#include <cstdint>
#include <vector>

#include "core/image.h"

namespace sb {

struct FernParams {
  int cellsX = 40, cellsY = 30;    // the small image, cells
  int samplesPerCellSide = 4;      // samples x samples raw readings per cell (sparse grid)
  int ferns = 500;                 // codes per frame
  int testsPerFern = 4;            // bits per code (2^tests values)
  double thresholdRangeM = 0.5;    // metres: test thresholds uniform in [-range, range] around the mean depth
  double minValidCells = 0.3;      // fraction of cells with depth needed for a code (else no code)
  uint32_t seed = 1;               // of the tests' cells and thresholds (fixed: codes comparable across runs)
};

// One code per fern (each < 2^testsPerFern).
struct FernCode {
  std::vector<uint8_t> codes;
  bool valid() const { return !codes.empty(); }
  // Fraction of ferns whose codes differ, in [0, 1] (Glocker et al.'s block-wise Hamming distance). Codes of
  // different sizes are fully dissimilar (1).
  double dissimilarity(const FernCode& other) const;
};

class FernEncoder {
 public:
  explicit FernEncoder(const FernParams& params);
  // The code of a raw depth frame (`metresPerUnit` metres per raw unit; 0 = no reading); invalid (empty) when
  // fewer than minValidCells of the cells hold depth.
  FernCode encode(const DepthRaw& depth, double metresPerUnit) const;
  const FernParams& params() const { return params_; }

 private:
  struct Test {
    int cell;          // index into the small image
    float threshold;   // metres, relative to the mean valid depth
  };
  FernParams params_;
  std::vector<Test> tests_;  // ferns x testsPerFern
};

}  // namespace sb
