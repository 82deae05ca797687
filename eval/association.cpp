// Timestamp association, TUM benchmark convention: every (estimate, ground truth) pair within the maximum
// time difference is a candidate; candidates are accepted greedily from the smallest time difference up,
// each pose used at most once; the accepted pairs are returned in increasing estimate time.

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>

#include "core/error.h"
#include "eval/trajectory_eval.h"

namespace sb {
namespace {

struct Candidate {
  double dt;  // seconds, absolute time difference after the offset
  size_t est;
  size_t gt;
};

void checkOptions(const AssociationOptions& options) {
  if (!std::isfinite(options.maxTimeDifference) || options.maxTimeDifference < 0.0) {
    throw Error("association: max time difference " + std::to_string(options.maxTimeDifference) +
                " s is invalid; give a finite value >= 0 (TUM convention: 0.02)");
  }
  if (!std::isfinite(options.timeOffset)) {
    throw Error("association: time offset is not finite; give a number of seconds (0 for none)");
  }
}

void checkTimestamps(const Trajectory& trajectory, const char* what) {
  for (size_t i = 0; i < trajectory.size(); ++i) {
    if (!std::isfinite(trajectory[i].timestamp)) {
      throw Error(std::string("association: ") + what + " pose " + std::to_string(i) +
                  " has a non-finite timestamp; fix the trajectory file");
    }
  }
}

}  // namespace

std::vector<std::pair<size_t, size_t>> associate(const Trajectory& estimate, const Trajectory& groundTruth,
                                                 const AssociationOptions& options) {
  checkOptions(options);
  checkTimestamps(estimate, "estimate");
  checkTimestamps(groundTruth, "ground truth");

  // Ground-truth indices ordered by time, so each estimate's window is found by binary search (the input
  // need not be sorted).
  std::vector<size_t> gtOrder(groundTruth.size());
  std::iota(gtOrder.begin(), gtOrder.end(), size_t{0});
  std::stable_sort(gtOrder.begin(), gtOrder.end(),
                   [&](size_t a, size_t b) { return groundTruth[a].timestamp < groundTruth[b].timestamp; });
  std::vector<double> gtTimes(gtOrder.size());
  for (size_t k = 0; k < gtOrder.size(); ++k) gtTimes[k] = groundTruth[gtOrder[k]].timestamp;

  std::vector<Candidate> candidates;
  for (size_t e = 0; e < estimate.size(); ++e) {
    const double t = estimate[e].timestamp + options.timeOffset;
    auto it = std::lower_bound(gtTimes.begin(), gtTimes.end(), t - options.maxTimeDifference);
    for (; it != gtTimes.end() && *it <= t + options.maxTimeDifference; ++it) {
      const size_t k = static_cast<size_t>(it - gtTimes.begin());
      candidates.push_back({std::abs(*it - t), e, gtOrder[k]});
    }
  }
  // Smallest difference first; ties broken by indices so the result never depends on sort stability.
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return std::tie(a.dt, a.est, a.gt) < std::tie(b.dt, b.est, b.gt);
  });

  std::vector<bool> estUsed(estimate.size(), false), gtUsed(groundTruth.size(), false);
  std::vector<std::pair<size_t, size_t>> matches;
  for (const auto& c : candidates) {
    if (estUsed[c.est] || gtUsed[c.gt]) continue;
    estUsed[c.est] = gtUsed[c.gt] = true;
    matches.emplace_back(c.est, c.gt);
  }
  std::sort(matches.begin(), matches.end(), [&](const auto& a, const auto& b) {
    return std::make_pair(estimate[a.first].timestamp, a.first) <
           std::make_pair(estimate[b.first].timestamp, b.first);
  });
  return matches;
}

}  // namespace sb
