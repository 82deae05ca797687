#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "core/error.h"
#include "eval/matched_poses.h"
#include "eval/rigid_alignment.h"
#include "eval/trajectory_eval.h"

namespace sb {
namespace {

constexpr size_t kMinAteMatches = 3;  // a rigid alignment needs at least three point pairs

double median(std::vector<double> v) {
  const size_t n = v.size();
  std::sort(v.begin(), v.end());
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

AteResult computeAte(const Trajectory& estimate, const Trajectory& groundTruth, const AssociationOptions& options,
                     const Eigen::Isometry3d* fixedAlignment) {
  const MatchedPoses m = matchPoses(estimate, groundTruth, options, kMinAteMatches);
  const size_t n = m.estimate.size();
  Eigen::Matrix3Xd est(3, n), gt(3, n);
  for (size_t i = 0; i < n; ++i) {
    est.col(static_cast<Eigen::Index>(i)) = m.estimate[i].position();
    gt.col(static_cast<Eigen::Index>(i)) = m.groundTruth[i].position();
  }

  AteResult r;
  r.matches = n;
  r.alignment = fixedAlignment ? *fixedAlignment : alignRigid(est, gt, "estimate", "ground truth");
  r.timestamps.resize(n);
  r.errors.resize(n);
  r.unalignedErrors.resize(n);
  const Eigen::Isometry3d estFirstInv = m.estimate.front().T_camera_to_world.inverse();
  const Eigen::Isometry3d gtFirstInv = m.groundTruth.front().T_camera_to_world.inverse();
  double sumSq = 0.0;
  for (size_t i = 0; i < n; ++i) {
    r.timestamps[i] = m.estimate[i].timestamp;
    r.errors[i] = (r.alignment * m.estimate[i].position() - m.groundTruth[i].position()).norm();
    sumSq += r.errors[i] * r.errors[i];
    // The paper's measure: both trajectories relative to their first matched pose, translations compared.
    const Eigen::Vector3d estRel = (estFirstInv * m.estimate[i].T_camera_to_world).translation();
    const Eigen::Vector3d gtRel = (gtFirstInv * m.groundTruth[i].T_camera_to_world).translation();
    r.unalignedErrors[i] = (estRel - gtRel).norm();
  }
  const double count = static_cast<double>(n);
  r.rmse = std::sqrt(sumSq / count);
  r.mean = std::accumulate(r.errors.begin(), r.errors.end(), 0.0) / count;
  r.median = median(r.errors);
  r.max = *std::max_element(r.errors.begin(), r.errors.end());
  r.unalignedMean = std::accumulate(r.unalignedErrors.begin(), r.unalignedErrors.end(), 0.0) / count;
  return r;
}

Eigen::Isometry3d alignFrames(const Trajectory& estimate, const Trajectory& groundTruth,
                              const AssociationOptions& options) {
  const MatchedPoses m = matchPoses(estimate, groundTruth, options, kMinAteMatches);
  const Eigen::Index n = static_cast<Eigen::Index>(m.estimate.size());
  Eigen::Matrix3Xd est(3, 4 * n), gt(3, 4 * n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Isometry3d& e = m.estimate[size_t(i)].T_camera_to_world;
    const Eigen::Isometry3d& g = m.groundTruth[size_t(i)].T_camera_to_world;
    est.col(4 * i) = e.translation();
    gt.col(4 * i) = g.translation();
    for (int a = 0; a < 3; ++a) {
      est.col(4 * i + 1 + a) = e * (kFrameLeverM * Eigen::Vector3d::Unit(a));
      gt.col(4 * i + 1 + a) = g * (kFrameLeverM * Eigen::Vector3d::Unit(a));
    }
  }
  return alignRigid(est, gt, "estimate", "ground truth");
}

}  // namespace sb
