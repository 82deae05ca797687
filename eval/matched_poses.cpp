#include "eval/matched_poses.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include "core/error.h"

namespace sb {
namespace {

std::string timeRange(const Trajectory& t, double offset) {
  if (t.empty()) return "no poses";
  double lo = t.front().timestamp, hi = lo;
  for (const auto& p : t) {
    lo = std::min(lo, p.timestamp);
    hi = std::max(hi, p.timestamp);
  }
  char buf[128];
  std::snprintf(buf, sizeof buf, "%zu poses, %.6f .. %.6f s", t.size(), lo + offset, hi + offset);
  return buf;
}

}  // namespace

MatchedPoses matchPoses(const Trajectory& estimate, const Trajectory& groundTruth,
                        const AssociationOptions& options, size_t minMatches) {
  if (estimate.empty()) throw Error("evaluation: the estimated trajectory has no poses");
  if (groundTruth.empty()) throw Error("evaluation: the ground-truth trajectory has no poses");
  const auto pairs = associate(estimate, groundTruth, options);
  if (pairs.size() < minMatches) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%g s", options.maxTimeDifference);
    const std::string ranges = "estimate (with offset " + std::to_string(options.timeOffset) +
                               " s): " + timeRange(estimate, options.timeOffset) +
                               "; ground truth: " + timeRange(groundTruth, 0.0);
    if (pairs.empty()) {
      throw Error("evaluation: no estimate pose has a ground-truth pose within " + std::string(buf) +
                  " (no overlap in time). " + ranges +
                  ". Check that both files are of the same sequence, or set the time offset / max time "
                  "difference");
    }
    throw Error("evaluation: only " + std::to_string(pairs.size()) + " poses associate within " + buf +
                ", at least " + std::to_string(minMatches) + " are needed. " + ranges);
  }
  MatchedPoses out;
  out.estimate.reserve(pairs.size());
  out.groundTruth.reserve(pairs.size());
  for (const auto& [e, g] : pairs) {
    out.estimate.push_back(estimate[e]);
    out.groundTruth.push_back(groundTruth[g]);
  }
  return out;
}

}  // namespace sb
