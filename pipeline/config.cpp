#include "pipeline/config.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "core/config_reader.h"
#include "core/error.h"

namespace sb {

namespace {

// One scalar field: its JSON key, where it lives, and the allowed closed range.
struct FloatField {
  const char* key;
  float PipelineConfig::*member;
  double minimum, maximum;
};
struct IntField {
  const char* key;
  int PipelineConfig::*member;
  int minimum, maximum;
};

const std::vector<FloatField>& floatFields() {
  static const std::vector<FloatField> fields = {
      {"bilateral_spatial_sigma_px", &PipelineConfig::bilateralSpatialSigma, 0.1, 100.0},
      {"volume_view_distance_m", &PipelineConfig::volumeViewDistance, 0.0, 10.0},
      {"volume_shift_threshold_m", &PipelineConfig::volumeShiftThreshold, 0.05, 100.0},
      {"bilateral_range_sigma_m", &PipelineConfig::bilateralRangeSigma, 1e-4, 10.0},
      {"half_sample_max_difference_m", &PipelineConfig::halfSampleMaxDifference, 1e-4, 10.0},
      {"icp_distance_threshold_m", &PipelineConfig::icpDistanceThreshold, 1e-4, 10.0},
      {"icp_normal_threshold", &PipelineConfig::icpNormalThreshold, -1.0, 1.0},
      {"tracked_max_residual_m", &PipelineConfig::trackedMaxResidual, 0.0, 10.0},
      {"tracked_min_inliers", &PipelineConfig::trackedMinInliers, 0.0, 1.0},
      {"constrained_min_conditioning", &PipelineConfig::constrainedMinConditioning, 0.0, 1.0},
      {"volume_size_m", &PipelineConfig::volumeSize, 0.1, 100.0},
      {"mu_m", &PipelineConfig::mu, 1e-4, 10.0},
      {"near_plane_m", &PipelineConfig::nearPlane, 0.0, 100.0},
      {"far_plane_m", &PipelineConfig::farPlane, 0.01, 100.0},
      {"raycast_large_step_mu", &PipelineConfig::raycastLargeStep, 0.01, 10.0},
      {"raycast_small_step_voxels", &PipelineConfig::raycastSmallStep, 0.01, 10.0},
      {"raycast_small_step_below_tsdf", &PipelineConfig::raycastSmallStepBelow, 0.0, 1.0},
      {"render_ambient", &PipelineConfig::renderAmbient, 0.0, 1.0},
      {"relocalise_min_pair_agreement", &PipelineConfig::relocaliseMinPairAgreement, 0.0, 1.0},
      {"depth_noise_disparity_px", &PipelineConfig::depthNoiseDisparityPx, 0.0, 10.0},
      {"depth_noise_baseline_m", &PipelineConfig::depthNoiseBaselineM, 0.001, 10.0},
      {"relocalise_agreement_margin", &PipelineConfig::relocaliseAgreementMargin, 0.0, 1.0},
      {"relocalise_min_conditioning", &PipelineConfig::relocaliseMinConditioning, 0.0, 1.0},
      {"relocalise_max_motion_m", &PipelineConfig::relocaliseMaxMotion, 0.0, 10.0},
      {"relocalise_max_rotation_deg", &PipelineConfig::relocaliseMaxRotationDeg, 0.0, 180.0},
      {"keyframe_min_dissimilarity", &PipelineConfig::keyframeMinDissimilarity, 0.0, 1.0},
  };
  return fields;
}

const std::vector<IntField>& intFields() {
  static const std::vector<IntField> fields = {
      {"bilateral_radius_px", &PipelineConfig::bilateralRadius, 0, 8},
      {"bootstrap_frames", &PipelineConfig::bootstrapFrames, 1, 1000},
      {"volume_resolution", &PipelineConfig::volumeResolution, 8, 1024},
      {"max_weight", &PipelineConfig::maxWeight, 1, 32767},
      {"quality_block_px", &PipelineConfig::qualityBlockPixels, 1, 256},
      {"lost_after_failed_frames", &PipelineConfig::lostAfterFailedFrames, 1, 1000},
      {"relocalise_candidates", &PipelineConfig::relocaliseCandidates, 0, 32},
      {"relocalise_confirm_frames", &PipelineConfig::relocaliseConfirmFrames, 1, 100},
      {"relocalise_csr", &PipelineConfig::relocaliseCsr, 1, 8},
      {"keyframe_capacity", &PipelineConfig::keyframeCapacity, 1, 100000},
      {"relocalise_kept_map_mib", &PipelineConfig::relocaliseKeptMapMib, 0, 1048576},
  };
  return fields;
}

std::string rangeText(double minimum, double maximum) {
  std::ostringstream s;
  s << "[" << minimum << ", " << maximum << "]";
  return s.str();
}

void checkRange(const std::string& where, const char* key, double value, double minimum, double maximum) {
  if (!(value >= minimum && value <= maximum)) {
    std::ostringstream s;
    s << where << ": '" << key << "' = " << value << " is not allowed: expected a value in " << rangeText(minimum, maximum)
      << "; fix the value";
    throw Error(s.str());
  }
}

// "opencl_platform" / "opencl_device": a non-negative index or a name substring, stored as text.
void readSelector(ConfigReader& r, const char* key, std::string& out) {
  const nlohmann::json* v = r.raw(key);
  if (!v) return;
  if (v->is_number_integer() && v->get<long long>() >= 0)
    out = std::to_string(v->get<long long>());
  else if (v->is_string())
    out = v->get<std::string>();
  else
    r.fail(key, "an index (0, 1, ...) or a name substring like \"NVIDIA\" (\"\" = automatic choice)");
}

}  // namespace

const char* volumeModeName(VolumeMode mode) {
  switch (mode) {
    case VolumeMode::moving: return "moving";
    case VolumeMode::fixed: return "fixed";
    case VolumeMode::automatic: break;
  }
  return "auto";
}

const char* backendKindName(BackendKind kind) {
  switch (kind) {
    case BackendKind::cpu: return "cpu";
    case BackendKind::opencl: return "opencl";
    case BackendKind::automatic: break;
  }
  return "auto";
}

void validateConfig(const PipelineConfig& c) {
  const std::string where = "pipeline config";
  for (const auto& f : floatFields()) checkRange(where, f.key, c.*(f.member), f.minimum, f.maximum);
  for (const auto& f : intFields()) checkRange(where, f.key, c.*(f.member), f.minimum, f.maximum);
  for (int i = 0; i < 3; ++i) checkRange(where, "initial_position", c.initialPosition[i], 0.0, 1.0);
  if (c.volumeResolution % 8 != 0)
    throw Error(where + ": 'volume_resolution' = " + std::to_string(c.volumeResolution) +
                " must be a multiple of 8 (e.g. 64, 128, 256, 512)");
  if (c.relocaliseCsr != 1 && c.relocaliseCsr != 2 && c.relocaliseCsr != 4 && c.relocaliseCsr != 8)
    throw Error(where + ": 'relocalise_csr' = " + std::to_string(c.relocaliseCsr) + " must be 1, 2, 4 or 8");
  if (c.farPlane <= c.nearPlane)
    throw Error(where + ": 'far_plane_m' must be larger than 'near_plane_m' (" + std::to_string(c.farPlane) +
                " <= " + std::to_string(c.nearPlane) + ")");
  if (c.openclHalfStorage && c.backend == BackendKind::cpu)
    throw Error(where + ": 'opencl_half_storage' = true needs 'backend' opencl or auto (the cpu backend stores " +
                "float only)");
  validateKnobs(c.knobs);
}

PipelineConfig parseConfig(const nlohmann::json& j, const PipelineConfig& base, const std::string& where) {
  ConfigReader r(j, where);
  PipelineConfig c = base;
  for (const auto& f : floatFields()) r.number(f.key, c.*(f.member), f.minimum, f.maximum);
  for (const auto& f : intFields()) r.integer(f.key, c.*(f.member), f.minimum, f.maximum);
  std::vector<double> position(c.initialPosition.begin(), c.initialPosition.end());
  r.numbers("initial_position", position, 0.0, 1.0, 3, 3, "[x, y, z], fractions of the volume side");
  for (int i = 0; i < 3; ++i) c.initialPosition[i] = static_cast<float>(position[i]);
  r.boolean("empty_space_skipping", c.emptySpaceSkipping);
  r.boolean("relocalise", c.relocalise);
  std::string volumeMode = volumeModeName(c.volumeMode);
  r.string("volume_mode", volumeMode, {"auto", "moving", "fixed"});
  c.volumeMode = volumeMode == "moving" ? VolumeMode::moving
                 : volumeMode == "fixed" ? VolumeMode::fixed
                                         : VolumeMode::automatic;
  std::string backend = backendKindName(c.backend);
  r.string("backend", backend, {"auto", "cpu", "opencl"});
  c.backend = backend == "cpu" ? BackendKind::cpu : backend == "opencl" ? BackendKind::opencl : BackendKind::automatic;
  readSelector(r, "opencl_platform", c.openclPlatform);
  readSelector(r, "opencl_device", c.openclDevice);
  if (const nlohmann::json* v = r.raw("opencl_source_dir")) {
    if (!v->is_string()) r.fail("opencl_source_dir", "a directory path (\"\" = the kernels embedded in the binary)");
    c.openclSourceDir = v->get<std::string>();
  }
  r.boolean("opencl_half_storage", c.openclHalfStorage);
  if (const nlohmann::json* v = r.raw("knobs")) {
    const std::string example = "a knob list like \"csr=1,icp=1e-5,pd=10:5:4,tr=1,ir=2\"";
    if (!v->is_string()) r.fail("knobs", example);
    try {
      c.knobs = parseKnobs(v->get<std::string>(), c.knobs);
    } catch (const Error& e) {
      r.fail("knobs", example + " (" + e.what() + ")");
    }
  }
  r.finish();
  try {
    validateConfig(c);
  } catch (const Error& e) {
    throw Error(where + ": " + e.what());
  }
  return c;
}

PipelineConfig loadConfigFile(const std::string& path, const PipelineConfig& base) {
  return parseConfig(readJsonConfig(path, "config file"), base, path);  // bounded nesting, names the file
}

nlohmann::json configToJson(const PipelineConfig& c) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& f : floatFields()) j[f.key] = c.*(f.member);
  for (const auto& f : intFields()) j[f.key] = c.*(f.member);
  j["initial_position"] = {c.initialPosition[0], c.initialPosition[1], c.initialPosition[2]};
  j["empty_space_skipping"] = c.emptySpaceSkipping;
  j["relocalise"] = c.relocalise;
  j["volume_mode"] = volumeModeName(c.volumeMode);
  j["backend"] = backendKindName(c.backend);
  j["opencl_platform"] = c.openclPlatform;
  j["opencl_device"] = c.openclDevice;
  j["opencl_half_storage"] = c.openclHalfStorage;
  j["opencl_source_dir"] = c.openclSourceDir;
  j["knobs"] = formatKnobs(c.knobs);
  return j;
}

}  // namespace sb
