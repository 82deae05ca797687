#include "pipeline/config.h"

#include <cmath>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "core/json_text.h"

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
  };
  return fields;
}

const std::vector<IntField>& intFields() {
  static const std::vector<IntField> fields = {
      {"bilateral_radius_px", &PipelineConfig::bilateralRadius, 0, 8},
      {"bootstrap_frames", &PipelineConfig::bootstrapFrames, 1, 1000},
      {"volume_resolution", &PipelineConfig::volumeResolution, 8, 1024},
      {"max_weight", &PipelineConfig::maxWeight, 1, 32767},
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
    s << where << ": '" << key << "' = " << value << " is out of range; allowed " << rangeText(minimum, maximum);
    throw Error(s.str());
  }
}

// "opencl_platform" / "opencl_device": a non-negative index or a name substring, stored as text.
std::string parseSelector(const std::string& where, const std::string& key, const nlohmann::json& v) {
  if (v.is_number_integer() && v.get<long long>() >= 0) return std::to_string(v.get<long long>());
  if (v.is_string()) return v.get<std::string>();
  throw Error(where + ": '" + key + "' must be an index (0, 1, ...) or a name substring like \"NVIDIA\" (\"\" = " +
              "automatic choice), got " + v.dump());
}

}  // namespace

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
  if (c.farPlane <= c.nearPlane)
    throw Error(where + ": 'far_plane_m' must be larger than 'near_plane_m' (" + std::to_string(c.farPlane) +
                " <= " + std::to_string(c.nearPlane) + ")");
  if (c.openclHalfStorage && c.backend == BackendKind::cpu)
    throw Error(where + ": 'opencl_half_storage' = true needs 'backend' opencl or auto (the cpu backend stores " +
                "float only)");
  validateKnobs(c.knobs);
}

PipelineConfig parseConfig(const nlohmann::json& j, const PipelineConfig& base, const std::string& where) {
  if (!j.is_object()) throw Error(where + ": the pipeline config must be a JSON object");
  PipelineConfig c = base;
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string& key = it.key();
    const nlohmann::json& v = it.value();
    bool known = false;
    for (const auto& f : floatFields()) {
      if (key != f.key) continue;
      if (!v.is_number()) throw Error(where + ": '" + key + "' must be a number, got " + v.dump());
      checkRange(where, f.key, v.get<double>(), f.minimum, f.maximum);
      c.*(f.member) = v.get<float>();
      known = true;
    }
    for (const auto& f : intFields()) {
      if (key != f.key) continue;
      if (!v.is_number_integer()) throw Error(where + ": '" + key + "' must be an integer, got " + v.dump());
      checkRange(where, f.key, v.get<double>(), f.minimum, f.maximum);
      c.*(f.member) = v.get<int>();
      known = true;
    }
    if (key == "initial_position") {
      if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
        throw Error(where + ": 'initial_position' must be an array of 3 numbers (fractions of the volume side), got " +
                    v.dump());
      for (int i = 0; i < 3; ++i) {
        checkRange(where, "initial_position", v[i].get<double>(), 0.0, 1.0);
        c.initialPosition[i] = v[i].get<float>();
      }
      known = true;
    } else if (key == "empty_space_skipping") {
      if (!v.is_boolean()) throw Error(where + ": 'empty_space_skipping' must be true or false, got " + v.dump());
      c.emptySpaceSkipping = v.get<bool>();
      known = true;
    } else if (key == "backend") {
      const std::string name = v.is_string() ? v.get<std::string>() : "";
      if (name == "auto") c.backend = BackendKind::automatic;
      else if (name == "cpu") c.backend = BackendKind::cpu;
      else if (name == "opencl") c.backend = BackendKind::opencl;
      else throw Error(where + ": 'backend' must be \"auto\", \"cpu\" or \"opencl\", got " + v.dump());
      known = true;
    } else if (key == "opencl_platform") {
      c.openclPlatform = parseSelector(where, key, v);
      known = true;
    } else if (key == "opencl_device") {
      c.openclDevice = parseSelector(where, key, v);
      known = true;
    } else if (key == "opencl_source_dir") {
      if (!v.is_string())
        throw Error(where + ": 'opencl_source_dir' must be a directory path (\"\" = the embedded kernels), got " +
                    v.dump());
      c.openclSourceDir = v.get<std::string>();
      known = true;
    } else if (key == "opencl_half_storage") {
      if (!v.is_boolean()) throw Error(where + ": 'opencl_half_storage' must be true or false, got " + v.dump());
      c.openclHalfStorage = v.get<bool>();
      known = true;
    } else if (key == "knobs") {
      if (!v.is_string())
        throw Error(where + ": 'knobs' must be a string like \"csr=1,icp=1e-5,pd=10:5:4,tr=1,ir=2\", got " + v.dump());
      try {
        c.knobs = parseKnobs(v.get<std::string>(), c.knobs);
      } catch (const Error& e) {
        throw Error(where + ": 'knobs': " + e.what());
      }
      known = true;
    }
    if (!known) {
      const nlohmann::json defaults = configToJson(PipelineConfig{});
      std::string keys;
      for (auto field = defaults.begin(); field != defaults.end(); ++field)
        keys += (keys.empty() ? "" : ", ") + field.key();
      throw Error(where + ": unknown key '" + key + "' (known keys: " + keys + ")");
    }
  }
  try {
    validateConfig(c);
  } catch (const Error& e) {
    throw Error(where + ": " + e.what());
  }
  return c;
}

PipelineConfig loadConfigFile(const std::string& path, const PipelineConfig& base) {
  return parseConfig(readJsonFile(path, "config file"), base, path);  // bounded nesting, names the file
}

nlohmann::json configToJson(const PipelineConfig& c) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& f : floatFields()) j[f.key] = c.*(f.member);
  for (const auto& f : intFields()) j[f.key] = c.*(f.member);
  j["initial_position"] = {c.initialPosition[0], c.initialPosition[1], c.initialPosition[2]};
  j["empty_space_skipping"] = c.emptySpaceSkipping;
  j["backend"] = backendKindName(c.backend);
  j["opencl_platform"] = c.openclPlatform;
  j["opencl_device"] = c.openclDevice;
  j["opencl_half_storage"] = c.openclHalfStorage;
  j["opencl_source_dir"] = c.openclSourceDir;
  j["knobs"] = formatKnobs(c.knobs);
  return j;
}

}  // namespace sb
