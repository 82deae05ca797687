#pragma once
// The approximation knobs of KinectFusion (architecture.md D2). They are passed to the pipeline per frame and
// may change between any two frames.

#include <array>
#include <string>
#include <vector>

namespace sb {

struct Knobs {
  int csr = 1;                                // compute size ratio: input subsampled by 1, 2, 4 or 8
  double icpThreshold = 1e-5;                 // ICP early stop when the update norm is below this (0 = never)
  std::array<int, 3> pyramidIterations{10, 5, 4};  // max ICP iterations per level: finest, mid, coarsest
  int trackingRate = 1;                       // track every n-th frame
  int integrationRate = 2;                    // integrate every n-th frame

  bool operator==(const Knobs& o) const {
    return csr == o.csr && icpThreshold == o.icpThreshold && pyramidIterations == o.pyramidIterations &&
           trackingRate == o.trackingRate && integrationRate == o.integrationRate;
  }
  bool operator!=(const Knobs& o) const { return !(*this == o); }
};

// Valid ranges (checked by validateKnobs): csr in {1, 2, 4, 8}; icp in [0, 1]; pd0 in [1, kMaxIterations],
// pd1 and pd2 in [0, kMaxIterations]; tr and ir in [1, kMaxRate].
constexpr int kMaxIterations = 100;
constexpr int kMaxRate = 1000;
// A compute size ratio the pipeline runs at: 1, 2, 4 or 8.
constexpr bool validCsr(int csr) { return csr == 1 || csr == 2 || csr == 4 || csr == 8; }

// "default" (SLAMBench's settings) or "accurate"; throws sb::Error naming the preset otherwise.
Knobs knobPreset(const std::string& name);

// Throws sb::Error naming the knob, its value and the allowed values when a knob is out of range.
void validateKnobs(const Knobs& knobs);

// Parses "csr=2,icp=1e-4,pd=8:5:4,tr=1,ir=2" (any subset, any order) on top of `base` and validates the
// result. Throws sb::Error naming the offending item.
Knobs parseKnobs(const std::string& text, const Knobs& base = Knobs{});

// The same syntax, every knob: "csr=1,icp=1e-05,pd=10:5:4,tr=1,ir=2".
std::string formatKnobs(const Knobs& knobs);

// The knob names that can be pinned one by one (the daemon's ?CONTROL, runtime/knob_pins.h), in KNOBS order.
const std::vector<std::string>& pinnableKnobs();

}  // namespace sb
