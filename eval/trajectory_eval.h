#pragma once
// Trajectory evaluation: ATE (TUM benchmark convention), the SLAMBooster paper's unaligned mean translation
// error, RPE, and per-frame error (ITE).

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "core/trajectory.h"

namespace sb {

struct AssociationOptions {
  double maxTimeDifference = 0.02;  // seconds; pairs farther apart in time are not matched
  double timeOffset = 0.0;          // seconds added to the estimate's timestamps before matching
};

// Index pairs (estimate, ground truth) matched by nearest timestamp, each pose used at most once, in
// increasing time order.
std::vector<std::pair<size_t, size_t>> associate(const Trajectory& estimate, const Trajectory& groundTruth,
                                                 const AssociationOptions& options = {});

struct AteResult {
  size_t matches = 0;
  double rmse = 0, mean = 0, median = 0, max = 0;  // metres, after rigid (Horn) alignment of positions
  double unalignedMean = 0;  // metres: mean |p_est - p_gt| with both trajectories expressed relative to
                             // their first matched pose (the SLAMBooster paper's measure)
  Eigen::Isometry3d alignment = Eigen::Isometry3d::Identity();  // maps estimate positions onto ground truth
  std::vector<double> timestamps;                               // estimate timestamps of the matches
  std::vector<double> errors;           // aligned per-frame translation error (ITE), m
  std::vector<double> unalignedErrors;  // per-frame error of the unaligned measure, m
};

// Throws sb::Error when fewer than 3 poses associate or the positions are degenerate (collinear/identical).
// With `fixedAlignment` the estimate is not aligned to this ground truth but mapped by it (a run in a kept map
// measured in the frame fitted on the run that made the map: no refit).
AteResult computeAte(const Trajectory& estimate, const Trajectory& groundTruth,
                     const AssociationOptions& options = {}, const Eigen::Isometry3d* fixedAlignment = nullptr);

// The rigid transform from the estimate's world frame to the ground truth's, fitted on whole poses: each matched
// pose's position and the points kFrameLeverM along its camera's three axes (Horn, as computeAte). A run's
// frame measured this way is fixed by its orientations as well as its path: a straight drive's positions alone
// leave the rotation about the line free (fitted to centimetres of noise, it swung a second run 0.8 m beside
// the line by 10 cm). For a run in a kept map measured in the frame of the run that made it: computeAte's
// `fixedAlignment`. Throws sb::Error like computeAte.
constexpr double kFrameLeverM = 1.0;
Eigen::Isometry3d alignFrames(const Trajectory& estimate, const Trajectory& groundTruth,
                              const AssociationOptions& options = {});

struct RpeResult {
  size_t pairs = 0;
  double translationRmse = 0, translationMean = 0;  // metres per delta
  double rotationRmse = 0, rotationMean = 0;        // degrees per delta
};

// RPE over a fixed delta: `delta` frames (perSecond = false) or `delta` seconds (perSecond = true).
// Frames count matched poses: pose i pairs with matched pose i + delta. In seconds, pose i pairs with the
// first matched pose whose estimate timestamp is at least `delta` s later. Throws sb::Error for a delta that
// is not positive (or not whole in frames), fewer than 2 matches, or no pair `delta` apart.
RpeResult computeRpe(const Trajectory& estimate, const Trajectory& groundTruth, double delta, bool perSecond,
                     const AssociationOptions& options = {});

// Writes the per-frame errors as CSV: `timestamp,ate_error_m,unaligned_error_m`.
void writeIteCsv(const std::string& path, const AteResult& ate);

}  // namespace sb
