#include "pipeline/knobs.h"

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "core/input_file.h"

namespace sb {

namespace {

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::string current;
  for (char c : text) {
    if (c == separator) {
      parts.push_back(current);
      current.clear();
    } else if (c != ' ') {
      current += c;
    }
  }
  parts.push_back(current);
  return parts;
}

double parseNumber(const std::string& key, const std::string& value) {
  if (value.empty()) throw Error("knob '" + key + "' has no value (write " + key + "=VALUE)");
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  if (end != value.c_str() + value.size() || !std::isfinite(v))
    throw Error("knob '" + key + "': '" + value + "' is not a number");
  return v;
}

int parseInt(const std::string& key, const std::string& value) {
  const double v = parseNumber(key, value);
  if (v != std::floor(v) || std::fabs(v) > 1e9)
    throw Error("knob '" + key + "': '" + value + "' is not a whole number");
  return static_cast<int>(v);
}

}  // namespace

Knobs knobPreset(const std::string& name) {
  Knobs k;
  if (name == "default") return k;
  if (name == "accurate") {
    k.icpThreshold = 0.0;
    k.integrationRate = 1;
    return k;
  }
  throw Error("unknown knob preset " + quoteForMessage(name) + " (use 'default' or 'accurate')");
}

void validateKnobs(const Knobs& k) {
  if (!validCsr(k.csr))
    throw Error("knob csr=" + std::to_string(k.csr) + " is not allowed (use 1, 2, 4 or 8)");
  if (!(k.icpThreshold >= 0.0 && k.icpThreshold <= 1.0))
    throw Error("knob icp=" + std::to_string(k.icpThreshold) + " is out of range (use a value in [0, 1])");
  for (int level = 0; level < 3; ++level) {
    const int v = k.pyramidIterations[level];
    const int minimum = level == 0 ? 1 : 0;
    if (v < minimum || v > kMaxIterations)
      throw Error("knob pd" + std::to_string(level) + "=" + std::to_string(v) + " is out of range (use " +
                  std::to_string(minimum) + ".." + std::to_string(kMaxIterations) + " iterations)");
  }
  if (k.trackingRate < 1 || k.trackingRate > kMaxRate)
    throw Error("knob tr=" + std::to_string(k.trackingRate) + " is out of range (use 1.." + std::to_string(kMaxRate) +
                ")");
  if (k.integrationRate < 1 || k.integrationRate > kMaxRate)
    throw Error("knob ir=" + std::to_string(k.integrationRate) + " is out of range (use 1.." +
                std::to_string(kMaxRate) + ")");
}

Knobs parseKnobs(const std::string& text, const Knobs& base) {
  Knobs k = base;
  for (const std::string& item : split(text, ',')) {
    if (item.empty()) continue;
    const size_t eq = item.find('=');
    if (eq == std::string::npos)
      throw Error("knob item '" + item + "' has no '=' (expected e.g. csr=2,icp=1e-4,pd=8:5:4,tr=1,ir=2)");
    const std::string key = item.substr(0, eq);
    const std::string value = item.substr(eq + 1);
    if (key == "csr") {
      k.csr = parseInt(key, value);
    } else if (key == "icp") {
      k.icpThreshold = parseNumber(key, value);
    } else if (key == "pd") {
      const auto levels = split(value, ':');
      if (levels.size() != 3) throw Error("knob pd='" + value + "' needs three iteration counts like pd=10:5:4");
      for (int i = 0; i < 3; ++i) k.pyramidIterations[i] = parseInt("pd", levels[i]);
    } else if (key == "pd0" || key == "pd1" || key == "pd2") {
      k.pyramidIterations[key[2] - '0'] = parseInt(key, value);
    } else if (key == "tr") {
      k.trackingRate = parseInt(key, value);
    } else if (key == "ir") {
      k.integrationRate = parseInt(key, value);
    } else {
      throw Error("unknown knob '" + key + "' in '" + text + "' (known: csr, icp, pd, pd0, pd1, pd2, tr, ir)");
    }
  }
  validateKnobs(k);
  return k;
}

std::string formatKnobs(const Knobs& k) {
  std::ostringstream s;
  s << "csr=" << k.csr << ",icp=" << k.icpThreshold << ",pd=" << k.pyramidIterations[0] << ":"
    << k.pyramidIterations[1] << ":" << k.pyramidIterations[2] << ",tr=" << k.trackingRate
    << ",ir=" << k.integrationRate;
  return s.str();
}

const std::vector<std::string>& pinnableKnobs() {
  static const std::vector<std::string> knobs = {"csr", "icp", "pd0", "pd1", "pd2", "tr", "ir"};
  return knobs;
}

}  // namespace sb
