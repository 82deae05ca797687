// Relative pose error: for pairs (i, j) of matched poses `delta` apart, E = (G_i^-1 G_j)^-1 (P_i^-1 P_j) with
// G ground truth and P the estimate; the translation norm (m) and rotation angle (degrees) of E.

#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "eval/matched_poses.h"
#include "eval/trajectory_eval.h"

namespace sb {
namespace {

constexpr size_t kMinRpeMatches = 2;      // one pair needs two matched poses
constexpr double kTimeToleranceS = 1e-6;  // TUM files print timestamps with 6 decimals
constexpr double kRadToDeg = 180.0 / EIGEN_PI;

// Index of the pose `delta` after i: `delta` frames later, or the first pose at least `delta` s later.
// Returns `n` when there is none.
size_t partnerOf(const Trajectory& poses, size_t i, double delta, bool perSecond) {
  const size_t n = poses.size();
  if (!perSecond) {
    const size_t j = i + static_cast<size_t>(delta);
    return j < n ? j : n;
  }
  const double target = poses[i].timestamp + delta - kTimeToleranceS;
  for (size_t j = i + 1; j < n; ++j) {
    if (poses[j].timestamp >= target) return j;
  }
  return n;
}

void checkDelta(double delta, bool perSecond) {
  if (!std::isfinite(delta) || delta <= 0.0) {
    throw Error("RPE: delta " + std::to_string(delta) + " is invalid; give a positive number of " +
                (perSecond ? "seconds" : "frames"));
  }
  if (!perSecond && std::floor(delta) != delta) {
    throw Error("RPE: delta " + std::to_string(delta) +
                " frames is not a whole number; give whole frames or measure the delta in seconds");
  }
}

}  // namespace

RpeResult computeRpe(const Trajectory& estimate, const Trajectory& groundTruth, double delta, bool perSecond,
                     const AssociationOptions& options) {
  checkDelta(delta, perSecond);
  const MatchedPoses m = matchPoses(estimate, groundTruth, options, kMinRpeMatches);
  const size_t n = m.estimate.size();
  RpeResult r;
  double sumT = 0, sumT2 = 0, sumR = 0, sumR2 = 0;
  for (size_t i = 0; i < n; ++i) {
    const size_t j = partnerOf(m.estimate, i, delta, perSecond);
    if (j >= n) break;  // partners only move later with i
    const Eigen::Isometry3d gtRel =
        m.groundTruth[i].T_camera_to_world.inverse() * m.groundTruth[j].T_camera_to_world;
    const Eigen::Isometry3d estRel =
        m.estimate[i].T_camera_to_world.inverse() * m.estimate[j].T_camera_to_world;
    const Eigen::Isometry3d err = gtRel.inverse() * estRel;
    const double t = err.translation().norm();
    const double rotDeg = Eigen::AngleAxisd(err.rotation()).angle() * kRadToDeg;
    sumT += t;
    sumT2 += t * t;
    sumR += rotDeg;
    sumR2 += rotDeg * rotDeg;
    ++r.pairs;
  }
  if (r.pairs == 0) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "RPE: no matched poses are %g %s apart: the %zu matched poses span %.6f s",
                  delta, perSecond ? "s" : "frames", n,
                  m.estimate.back().timestamp - m.estimate.front().timestamp);
    throw Error(std::string(buf) + "; use a smaller delta");
  }
  const double count = static_cast<double>(r.pairs);
  r.translationMean = sumT / count;
  r.translationRmse = std::sqrt(sumT2 / count);
  r.rotationMean = sumR / count;
  r.rotationRmse = std::sqrt(sumR2 / count);
  return r;
}

}  // namespace sb
