#include "pipeline/knobs.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <type_traits>
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

const KnobKey* findKnob(const std::string& name) {
  for (const KnobKey& key : kKnobKeys)
    if (name == key.name) return &key;
  return nullptr;
}

namespace {

std::string numberText(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// "1, 2, 4 or 8": the powers of two in the key's range.
std::string powersOfTwo(const KnobKey& key) {
  std::string list;
  std::string last;
  for (double v = 1; v <= key.maximum; v *= 2) {
    if (v < key.minimum) continue;
    if (!last.empty()) list += (list.empty() ? "" : ", ") + last;
    last = numberText(v);
  }
  return list.empty() ? last : list + " or " + last;
}

void validate(const KnobKey& key, const Knobs& k) {
  const double v = key.value(k);
  const std::string item = std::string("knob ") + key.name + "=" +
                           (key.isWhole() ? std::to_string(static_cast<int>(v)) : std::to_string(v));
  if (key.powerOfTwo) {
    const int i = static_cast<int>(v);
    if (v < key.minimum || v > key.maximum || (i & (i - 1)) != 0)
      throw Error(item + " is not allowed (use " + powersOfTwo(key) + ")");
    return;
  }
  if (!(v >= key.minimum && v <= key.maximum)) {
    if (key.isWhole())
      throw Error(item + " is out of range (use " + numberText(key.minimum) + ".." + numberText(key.maximum) +
                  key.unit + ")");
    throw Error(item + " is out of range (use a value in [" + numberText(key.minimum) + ", " +
                numberText(key.maximum) + "]" + key.unit + ")");
  }
}

std::string knownNames() {
  std::string list;
  for (const KnobKey& key : kKnobKeys) {
    if (key.level == 0) list += std::string(list.empty() ? "" : ", ") + kIterationsKnob;
    list += std::string(list.empty() ? "" : ", ") + key.name;
  }
  return list;
}

}  // namespace

void validateKnobs(const Knobs& k) {
  for (const KnobKey& key : kKnobKeys) validate(key, k);
}

Knobs parseKnobs(const std::string& text, const Knobs& base) {
  Knobs k = base;
  for (const std::string& item : split(text, ',')) {
    if (item.empty()) continue;
    const size_t eq = item.find('=');
    if (eq == std::string::npos)
      throw Error("knob item '" + item + "' has no '=' (expected e.g. " + formatKnobs(Knobs{}) + ")");
    const std::string name = item.substr(0, eq);
    const std::string value = item.substr(eq + 1);
    if (name == kIterationsKnob) {
      const auto levels = split(value, ':');
      if (levels.size() != k.pyramidIterations.size())
        throw Error("knob " + name + "='" + value + "' needs three iteration counts like " + name + "=10:5:4");
      for (size_t i = 0; i < levels.size(); ++i) k.pyramidIterations[i] = parseInt(name, levels[i]);
    } else if (const KnobKey* key = findKnob(name)) {
      key->set(k, key->isWhole() ? parseInt(name, value) : parseNumber(name, value));
    } else {
      throw Error("unknown knob '" + name + "' in '" + text + "' (known: " + knownNames() + ")");
    }
  }
  validateKnobs(k);
  return k;
}

std::string formatKnobs(const Knobs& k) {
  std::ostringstream s;
  forEachKnobField(k, [&s](const char* name, const auto& value) {
    s << (s.tellp() > 0 ? "," : "") << name << "=";
    if constexpr (std::is_arithmetic_v<std::decay_t<decltype(value)>>) {
      s << value;
    } else {
      for (size_t i = 0; i < value.size(); ++i) s << (i ? ":" : "") << value[i];
    }
  });
  return s.str();
}

const std::vector<std::string>& pinnableKnobs() {
  static const std::vector<std::string> knobs = [] {
    std::vector<std::string> names;
    for (const KnobKey& key : kKnobKeys) names.emplace_back(key.name);
    return names;
  }();
  return knobs;
}

nlohmann::json knobsToJson(const Knobs& k) {
  nlohmann::json j = nlohmann::json::object();
  forEachKnobField(k, [&j](const char* name, const auto& value) { j[name] = value; });
  return j;
}

}  // namespace sb
