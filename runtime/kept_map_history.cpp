#include "runtime/kept_map_history.h"

#include <algorithm>
#include <cstdio>

#include "odometry/wheel_faults.h"

namespace sb {

void KeptMapHistory::add(const DepthFrame& frame, const std::optional<Eigen::Isometry3d>& step) {
  if (!step) {
    clear();
  } else if (started_) {
    now_ = now_ * *step;
    pathM_ += step->translation().norm();
  }
  started_ = true;
  if (!views_.empty() && pathM_ - views_.back().pathM < kSpacingM) return;
  views_.push_back(View{frame, now_, pathM_});
  while (views_.size() > kMaxViews) views_.pop_front();
}

void KeptMapHistory::clear() {
  views_.clear();
  now_ = Eigen::Isometry3d::Identity();
  pathM_ = 0.0;
  started_ = false;
}

PathVerdict KeptMapHistory::check(const Eigen::Isometry3d& candidate, const PathTest& test,
                                  const TryView& tryView) const {
  PathVerdict v;
  const Eigen::Isometry3d toCandidate = candidate * now_.inverse();
  std::string views;
  for (auto it = views_.rbegin(); it != views_.rend(); ++it) {  // nearest first
    const double backM = pathM_ - it->pathM;
    if (backM < kSpacingM * 0.5) continue;  // the view in hand, or nearly: the candidate's own
    const Eigen::Isometry3d pose = toCandidate * it->wheels;
    const TrackAttempt a = tryView(it->frame, pose);
    ++v.views;
    const double coverage = a.modelCoverage;
    const double agreement = a.agreementInNoise.value_or(a.pairAgreement);
    const double moved = (a.T_camera_to_world.translation() - pose.translation()).norm();
    const double tolerance = kPlaceM + kSigmas * test.noisePerM * backM;
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s%.1f m %.3f/%.2f/%.3f", views.empty() ? "" : ", ", backM, agreement, coverage,
                  moved);
    views += buf;
    if (coverage < kCoveredShare) continue;
    ++v.covered;
    v.pathM = backM;
    v.worstAgreement = std::min(v.worstAgreement, agreement);
    if (agreement >= test.minAgreement && moved <= tolerance) ++v.fit;
  }
  char buf[160];
  std::snprintf(buf, sizeof buf, "%d of %d earlier views covered over %.1f m, %d fit (worst agreement %.3f, needed %.3f)",
                v.covered, v.views, v.pathM, v.fit, v.worstAgreement, test.minAgreement);
  v.why = std::string(buf) + " [metres back agreement/coverage/moved: " + views + "]";
  return v;
}

}  // namespace sb
