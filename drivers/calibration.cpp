#include "drivers/calibration.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/config_reader.h"
#include "core/error.h"
#include "core/image.h"
#include "core/json_text.h"
#include "drivers/camera_bounds.h"

namespace sb {

namespace {

using nlohmann::json;

// Largest image side accepted from a file, pixels (guards allocations against corrupt values).
constexpr int kMaxImageSide = kMaxDepthImageSide;
// Volume hints, metres: the range of the pipeline config's volume_size_m.
constexpr double kMinVolumeSize = 0.1, kMaxVolumeSize = 100.0;

// Each reads an optional key of calibration.json; a bad value fails through the config reader, naming the file,
// the key, the value and what is allowed. Keys nobody reads (sensor, frame_rate_hz, ...) are ignored.
std::optional<double> readNumber(ConfigReader& r, const char* key, double minValue, double maxValue,
                                 const std::string& expected) {
  const json* v = r.raw(key);
  if (!v) return std::nullopt;
  if (!v->is_number() || !(v->get<double>() >= minValue && v->get<double>() <= maxValue)) r.fail(key, expected);
  return v->get<double>();
}

std::optional<int> readSide(ConfigReader& r, const char* key) {
  const std::string expected = "an integer in [1, " + std::to_string(kMaxImageSide) + "] pixels";
  const json* v = r.raw(key);
  if (v && !v->is_number_integer()) r.fail(key, expected);
  const auto d = readNumber(r, key, 1, kMaxImageSide, expected);
  if (!d) return std::nullopt;
  return static_cast<int>(*d);
}

std::optional<float> readPixels(ConfigReader& r, const char* key, bool positive) {
  const double lo = positive ? std::numeric_limits<double>::min() : -1e6;
  const auto d = readNumber(r, key, lo, 1e6, positive ? "a positive number of pixels" : "a number of pixels");
  if (!d) return std::nullopt;
  if (positive && !(static_cast<float>(*d) > 0))  // 1e-300 is positive, and 0 as the float the pipeline uses
    r.fail(key, "a positive number of pixels (this one is 0 as a float)");
  return static_cast<float>(*d);
}

}  // namespace

Calibration readCalibration(const std::string& path) {
  // A directory, bad JSON, deep nesting or a non-object: names the file.
  ConfigReader r(readJsonConfig(path, "calibration"), "calibration '" + path + "'");

  Calibration c;
  c.path = path;
  c.width = readSide(r, "width");
  c.height = readSide(r, "height");
  c.fx = readPixels(r, "fx", true);
  c.fy = readPixels(r, "fy", true);
  c.cx = readPixels(r, "cx", false);
  c.cy = readPixels(r, "cy", false);
  c.depthScale = readNumber(r, "depth_scale", std::numeric_limits<double>::min(), 1e9,
                            "a positive number of raw units per metre");
  if (const json* v = r.raw("invalid_depth_values")) {
    const std::string expected = "an array of integers in [0, 65535]";
    if (!v->is_array()) r.fail("invalid_depth_values", expected);
    for (const json& e : *v) {
      if (!e.is_number_integer() || e.get<long long>() < 0 ||
          e.get<long long>() > std::numeric_limits<uint16_t>::max())
        r.fail("invalid_depth_values", expected + " (entry " + describeJson(e) + " is not)");
      c.invalidDepthValues.push_back(static_cast<uint16_t>(e.get<long long>()));
    }
  }
  r.string("format", c.format);  // free text, e.g. "tum" or "icl-nuim"
  // The ranges of the pipeline config's volume_size_m and initial_position, checked here so that the error
  // names this file and the value as written.
  c.volumeSize = readNumber(r, "volume_size_m", kMinVolumeSize, kMaxVolumeSize, "a volume side in metres in [0.1, 100]");
  if (const json* v = r.raw("volume_initial_position")) {
    const std::string expected = "an array [x, y, z] of fractions of the volume side, each in [0, 1]";
    if (!v->is_array() || v->size() != 3) r.fail("volume_initial_position", expected);
    std::array<double, 3> p{};
    for (size_t i = 0; i < 3; ++i) {
      if (!(*v)[i].is_number() || !((*v)[i].get<double>() >= 0.0 && (*v)[i].get<double>() <= 1.0))
        r.fail("volume_initial_position",
               expected + " (" + describeJson((*v)[i]) + " at index " + std::to_string(i) + " is not)");
      p[i] = (*v)[i].get<double>();
    }
    c.volumeInitialPosition = p;
  }
  return c;
}

void resolveCamera(SequenceInfo& info, const Calibration* calibration, const SequenceOptions& options,
                   const CameraDefaults& defaults) {
  std::vector<std::string> defaulted;
  const auto pick = [&](const char* name, const std::optional<float>& option,
                        const std::optional<float>* fromFile, float fallback) {
    if (option) return *option;
    if (fromFile && *fromFile) return **fromFile;
    defaulted.emplace_back(name);
    return fallback;
  };
  const Calibration* c = calibration;
  info.intrinsics.fx = pick("fx", options.fx, c ? &c->fx : nullptr, defaults.intrinsics.fx);
  info.intrinsics.fy = pick("fy", options.fy, c ? &c->fy : nullptr, defaults.intrinsics.fy);
  info.intrinsics.cx = pick("cx", options.cx, c ? &c->cx : nullptr, defaults.intrinsics.cx);
  info.intrinsics.cy = pick("cy", options.cy, c ? &c->cy : nullptr, defaults.intrinsics.cy);
  if (options.depthScale) {
    info.depthScale = *options.depthScale;
  } else if (c && c->depthScale) {
    info.depthScale = *c->depthScale;
  } else {
    info.depthScale = defaults.depthScale;
    defaulted.emplace_back("depth_scale");
  }
  if (!(info.depthScale > 0))
    throw Error("sequence '" + info.path + "': depth scale must be > 0 raw units per metre");
  if (c) {
    info.volumeSize = c->volumeSize;
    info.volumeInitialPosition = c->volumeInitialPosition;
  }
  if (!defaulted.empty()) {
    std::string names;
    for (const auto& n : defaulted) names += (names.empty() ? "" : ", ") + n;
    spdlog::warn("sequence '{}': {} not given by {} or the command line; using the defaults of {}", info.path,
                 names, c ? "'" + c->path + "'" : "a calibration.json", defaults.name);
  }
}

void checkIntrinsics(const SequenceInfo& info, const Calibration* calibration,
                     const SequenceOptions& options) {
  // The bounds every door shares (drivers/camera_bounds.h); a value that came from the defaults is not checked.
  struct Given {
    const char* name;
    bool fromOption, fromFile;
  };
  const Calibration* c = calibration;
  const Given given[] = {
      {"fx", options.fx.has_value(), c && c->fx.has_value()},
      {"fy", options.fy.has_value(), c && c->fy.has_value()},
      {"cx", options.cx.has_value(), c && c->cx.has_value()},
      {"cy", options.cy.has_value(), c && c->cy.has_value()},
      {"depth_scale", options.depthScale.has_value(), c && c->depthScale.has_value()},
  };
  for (const CameraBound& b : cameraBounds(info.intrinsics, info.depthScale)) {
    if (b.value >= b.lo && b.value <= b.hi) continue;
    for (const Given& g : given) {
      if (std::string(g.name) != b.name || (!g.fromOption && !g.fromFile)) continue;
      const std::string from =
          g.fromOption ? std::string("from the command line") : "from '" + calibration->path + "'";
      throw Error(cameraBoundMessage("sequence '" + info.path + "' (" + b.name + " " + from + ")", b,
                                     info.intrinsics));
    }
  }
}

std::vector<uint16_t> invalidDepthValues(const Calibration* calibration) {
  std::vector<uint16_t> values = {0, std::numeric_limits<uint16_t>::max()};
  if (calibration)
    values.insert(values.end(), calibration->invalidDepthValues.begin(),
                  calibration->invalidDepthValues.end());
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
  return values;
}

void normaliseInvalidDepth(DepthRaw& depth, const std::vector<uint16_t>& invalidValues) {
  for (const uint16_t invalid : invalidValues) {
    if (invalid == 0) continue;
    for (uint16_t& v : depth.pixels())
      if (v == invalid) v = 0;
  }
}

void writeCalibration(const std::string& path, const SequenceInfo& info) {
  json j;
  j["width"] = info.intrinsics.width;
  j["height"] = info.intrinsics.height;
  j["fx"] = info.intrinsics.fx;
  j["fy"] = info.intrinsics.fy;
  j["cx"] = info.intrinsics.cx;
  j["cy"] = info.intrinsics.cy;
  j["depth_scale"] = info.depthScale;
  if (!info.format.empty()) j["format"] = info.format;
  if (info.volumeSize) j["volume_size_m"] = *info.volumeSize;
  if (info.volumeInitialPosition) j["volume_initial_position"] = *info.volumeInitialPosition;
  std::ofstream out(path);
  out << j.dump(2) << '\n';
  out.flush();
  if (!out) throw Error("cannot write calibration '" + path + "': check that the directory is writable");
}

}  // namespace sb
