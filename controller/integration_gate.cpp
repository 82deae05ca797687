#include "controller/integration_gate.h"

#include "controller/tracking_evidence.h"

namespace sb {

void IntegrationParams::read(ConfigReader& r) {
  r.number("integrate_translation_m", translationM, 0.0, 10.0);
  r.number("integrate_translation_m_with_odometry", translationWithOdometryM, 0.0, 10.0);
  r.number("integrate_rotation_deg", rotationDeg, 0.0, 180.0);
  r.integer("integrate_max_gap_frames", maxGapFrames, 1, kMaxGap);
}

void IntegrationParams::toJson(nlohmann::json& j) const {
  j["integrate_translation_m"] = translationM;
  j["integrate_translation_m_with_odometry"] = translationWithOdometryM;
  j["integrate_rotation_deg"] = rotationDeg;
  j["integrate_max_gap_frames"] = maxGapFrames;
}

bool IntegrationGate::decide(const Eigen::Isometry3d& pose, bool eligible, bool odometry) {
  ++sinceFused_;
  if (!eligible) return false;
  const bool fuse = !fusedAny_ || sinceFused_ >= params_.maxGapFrames ||
                    translationBetween(lastFused_, pose) >=
                        (odometry ? params_.translationWithOdometryM : params_.translationM) ||
                    rotationBetweenDeg(lastFused_, pose) >= params_.rotationDeg;
  if (fuse) {
    lastFused_ = pose;
    fusedAny_ = true;
    sinceFused_ = 0;
  }
  return fuse;
}

}  // namespace sb
