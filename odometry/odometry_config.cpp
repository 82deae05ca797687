#include "odometry/odometry_config.h"

#include "core/config_reader.h"

namespace sb::odometry {

namespace {

// Each key once: its name, its member, its range.
struct Key {
  const char* name;
  double OdometryConfig::*member;
  double minimum, maximum;
};

constexpr Key kKeys[] = {
    {"max_speed_m_per_s", &OdometryConfig::maxSpeedMPerS, 0.01, 1000.0},
    {"max_acceleration_m_per_s2", &OdometryConfig::maxAccelerationMPerS2, 0.01, 10000.0},
    {"max_turn_rate_deg_per_s", &OdometryConfig::maxTurnRateDegPerS, 1.0, 100000.0},
    {"jump_agreement_margin", &OdometryConfig::jumpAgreementMargin, 0.0, 1.0},
    {"max_correction_m", &OdometryConfig::maxCorrectionM, 0.0, 100.0},
    {"noise_per_m", &OdometryConfig::noisePerM, 0.0, 1.0},
    {"noise_floor_m", &OdometryConfig::noiseFloorM, 1e-6, 1.0},
    {"noise_per_rad", &OdometryConfig::noisePerRad, 0.0, 1.0},
    {"noise_floor_rad", &OdometryConfig::noiseFloorRad, 1e-6, 1.0},
    {"icp_sigma_m", &OdometryConfig::icpSigmaM, 1e-6, 1.0},
    {"full_conditioning", &OdometryConfig::fullConditioning, 1e-6, 0.34},
    {"min_conditioning", &OdometryConfig::minConditioning, 0.0, 0.34},
    {"slip_sigmas", &OdometryConfig::slipSigmas, 0.5, 1000.0},
    {"slip_floor_m", &OdometryConfig::slipFloorM, 0.0, 10.0},
    {"max_distance_m", &OdometryConfig::maxDistanceM, 0.0, 10000.0},
    {"max_time_s", &OdometryConfig::maxTimeS, 0.0, 1e6},
    {"relocalise_tolerance_m", &OdometryConfig::relocaliseToleranceM, 0.0, 1000.0},
    {"max_extrapolation_s", &OdometryConfig::maxExtrapolationS, 0.0, 10.0},
    {"max_gap_s", &OdometryConfig::maxGapS, 0.001, 100.0},
    {"calibration_window_m", &OdometryConfig::calibrationWindowM, 0.0, 1e6},
    {"tilt_sigma_deg", &OdometryConfig::tiltSigmaDeg, 0.0, 90.0},
    {"mount_sigma_deg", &OdometryConfig::mountSigmaDeg, 0.0, 45.0},
    {"dispute_s", &OdometryConfig::disputeS, 0.0, 60.0},
    {"calm_s", &OdometryConfig::calmS, 0.0, 60.0},
    {"planar_prior_conditioning", &OdometryConfig::planarPriorConditioning, 0.0, 0.34},
    {"map_agreement_fraction", &OdometryConfig::mapAgreementFraction, 0.0, 1.0},
    {"max_unchecked_s", &OdometryConfig::maxUncheckedS, 0.0, 60.0},
    {"time_offset_s", &OdometryConfig::timeOffsetS, -10.0, 10.0},
    {"time_offset_range_s", &OdometryConfig::timeOffsetRangeS, 0.0, 1.0},
};

}  // namespace

void OdometryConfig::read(ConfigReader& r) {
  for (const Key& k : kKeys) r.number(k.name, this->*k.member, k.minimum, k.maximum);
}

nlohmann::json OdometryConfig::toJson() const {
  nlohmann::json j = nlohmann::json::object();
  for (const Key& k : kKeys) j[k.name] = this->*k.member;
  return j;
}

}  // namespace sb::odometry

namespace sb::odometry {

OdometryConfig odometryConfigFrom(const nlohmann::json& section, const std::string& where) {
  OdometryConfig c;
  if (section.is_null()) return c;
  // Read as the settings file's "odometry" key, so that messages name it as before the section had its own type.
  ConfigReader r(nlohmann::json{{"odometry", section}}, where);
  r.section("odometry", [&](ConfigReader& s) { c.read(s); });
  r.finish();
  return c;
}

}  // namespace sb::odometry
