#include "controller/tracking_evidence.h"

#include <algorithm>
#include <cstdio>
#include <vector>

#include "controller/pose_corrector.h"

namespace sb {

namespace {

constexpr double kDegPerRad = 57.29577951308232;

std::string format(const char* text, double value) {
  char buf[96];
  std::snprintf(buf, sizeof buf, text, value);
  return buf;
}

}  // namespace

void EvidenceParams::read(ConfigReader& r) {
  r.number("doubt_update_norm", maxUpdateNorm, 0.0, 10.0);
  r.number("doubt_inlier_drop_ratio", inlierDropRatio, 0.0, 1.0);
  r.integer("doubt_inlier_window_frames", inlierWindowFrames, 1, 1000);
  r.number("doubt_prediction_translation_m", predictionTranslationM, 0.0, 10.0);
  r.number("doubt_prediction_rotation_deg", predictionRotationDeg, 0.0, 180.0);
  r.number("doubt_conditioning", weakConditioning, 0.0, 1.0);
}

void EvidenceParams::toJson(nlohmann::json& j) const {
  j["doubt_update_norm"] = maxUpdateNorm;
  j["doubt_inlier_drop_ratio"] = inlierDropRatio;
  j["doubt_inlier_window_frames"] = inlierWindowFrames;
  j["doubt_prediction_translation_m"] = predictionTranslationM;
  j["doubt_prediction_rotation_deg"] = predictionRotationDeg;
  j["doubt_conditioning"] = weakConditioning;
}

double translationBetween(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.translation() - b.translation()).norm();
}

double rotationBetweenDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * kDegPerRad;
}

Eigen::Isometry3d MotionModel::predict(const Eigen::Isometry3d& previousPose) const {
  return nearestRigid(motion_ * previousPose);
}

void MotionModel::learn(const Eigen::Isometry3d& previousPose, const Eigen::Isometry3d& pose,
                        const TrackingQuality& quality, double lambda) {
  const Eigen::Isometry3d measured = nearestRigid(pose * previousPose.inverse());
  const Eigen::Isometry3d previous = motion_;
  motion_ = measured;
  if (known_ && lambda > 0 && quality.known) {
    const Twist learnt = blendByStructure(quality, transformToTwist(previous), transformToTwist(measured), lambda);
    if (learnt.allFinite()) motion_ = nearestRigid(twistToTransform(learnt));
  }
  known_ = true;
}

Doubt TrackingEvidence::judge(const Observation& o, const Eigen::Isometry3d& predicted, bool usePrediction) const {
  if (!o.tracked) return {Doubt::failed, "track failed"};
  if (o.quality.known && o.quality.icpConditioning < params_.weakConditioning)
    return {Doubt::unconstrained, format("weakly constrained (ICP conditioning %.2g", o.quality.icpConditioning) + ", " +
                                      weakDirectionName(o.quality.weakest) + ")"};
  const int pd0 = o.knobs.pyramidIterations[0];
  if (o.icpLevelIterations[0] >= pd0 && o.icpUpdateNorm > params_.maxUpdateNorm)
    return {Doubt::notConverged, format("ICP not converged (update %.2g)", o.icpUpdateNorm)};
  if (!inliers_.empty()) {
    std::vector<double> sorted(inliers_.begin(), inliers_.end());
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double median = sorted[sorted.size() / 2];
    if (o.inlierFraction < params_.inlierDropRatio * median)
      return {Doubt::inlierDrop, format("inliers dropped to %.2f", o.inlierFraction)};
  }
  if (usePrediction) {
    const double dt = translationBetween(o.pose, predicted);
    if (dt > params_.predictionTranslationM) return {Doubt::prediction, format("prediction off by %.3f m", dt)};
    const double dr = rotationBetweenDeg(o.pose, predicted);
    if (dr > params_.predictionRotationDeg) return {Doubt::prediction, format("prediction off by %.1f deg", dr)};
  }
  return {};
}

bool TrackingEvidence::offPrediction(const Observation& o, const Eigen::Isometry3d& predicted) const {
  return translationBetween(o.pose, predicted) > params_.predictionTranslationM ||
         rotationBetweenDeg(o.pose, predicted) > params_.predictionRotationDeg;
}

void TrackingEvidence::accept(const Observation& o) {
  if (!o.tracked) return;
  inliers_.push_back(o.inlierFraction);
  while (inliers_.size() > static_cast<size_t>(params_.inlierWindowFrames)) inliers_.pop_front();
}

}  // namespace sb
