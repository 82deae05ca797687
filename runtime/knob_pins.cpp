#include "runtime/knob_pins.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.h"

namespace sb {


namespace {

void set(Knobs& k, const std::string& knob, double v) {
  const int i = static_cast<int>(v);
  if (knob == "csr")
    k.csr = i;
  else if (knob == "icp")
    k.icpThreshold = v;
  else if (knob == "pd0")
    k.pyramidIterations[0] = i;
  else if (knob == "pd1")
    k.pyramidIterations[1] = i;
  else if (knob == "pd2")
    k.pyramidIterations[2] = i;
  else if (knob == "tr")
    k.trackingRate = i;
  else if (knob == "ir")
    k.integrationRate = i;
}

}  // namespace

void KnobPins::pin(const std::string& knob, double value) {
  const auto& known = pinnableKnobs();
  if (std::find(known.begin(), known.end(), knob) == known.end())
    throw Error("cannot pin unknown knob '" + knob + "'");
  std::ostringstream v;
  v << value;
  if (knob != "icp" && (value != std::floor(value) || std::abs(value) > 1e6))
    throw Error("pinned knob '" + knob + "' = " + v.str() + " must be an integer");
  Knobs probe;
  set(probe, knob, value);
  try {
    validateKnobs(probe);
  } catch (const Error& e) {
    throw Error("pinned knob '" + knob + "' = " + v.str() + ": " + e.what());
  }
  values_[knob] = value;
}

void KnobPins::unpin(const std::string& knob) {
  if (knob == "all") {
    values_.clear();
    return;
  }
  const auto& known = pinnableKnobs();
  if (std::find(known.begin(), known.end(), knob) == known.end())
    throw Error("cannot unpin unknown knob '" + knob + "'");
  values_.erase(knob);
}

Knobs KnobPins::apply(Knobs knobs) const {
  for (const auto& [knob, value] : values_) set(knobs, knob, value);
  return knobs;
}

std::vector<std::string> KnobPins::names() const {
  std::vector<std::string> n;
  for (const auto& knob : pinnableKnobs())
    if (values_.count(knob)) n.push_back(knob);
  return n;
}

nlohmann::json KnobPins::toJson() const {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [knob, value] : values_) j[knob] = value;
  return j;
}

KnobPins KnobPins::all(const Knobs& knobs) {
  validateKnobs(knobs);
  KnobPins pins;
  pins.values_ = {{"csr", knobs.csr},
                  {"icp", knobs.icpThreshold},
                  {"pd0", knobs.pyramidIterations[0]},
                  {"pd1", knobs.pyramidIterations[1]},
                  {"pd2", knobs.pyramidIterations[2]},
                  {"tr", knobs.trackingRate},
                  {"ir", knobs.integrationRate}};
  return pins;
}

}  // namespace sb
