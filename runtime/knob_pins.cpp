#include "runtime/knob_pins.h"

#include <cmath>
#include <sstream>

#include "core/error.h"

namespace sb {


namespace {

const KnobKey& known(const std::string& knob, const char* verb) {
  const KnobKey* key = findKnob(knob);
  if (!key) throw Error(std::string("cannot ") + verb + " unknown knob '" + knob + "'");
  return *key;
}

}  // namespace

void KnobPins::pin(const std::string& knob, double value) {
  const KnobKey& key = known(knob, "pin");
  std::ostringstream v;
  v << value;
  if (key.isWhole() && (value != std::floor(value) || std::abs(value) > 1e6))
    throw Error("pinned knob '" + knob + "' = " + v.str() + " must be an integer");
  Knobs probe;
  key.set(probe, value);
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
  values_.erase(known(knob, "unpin").name);
}

Knobs KnobPins::apply(Knobs knobs) const {
  for (const auto& [knob, value] : values_) findKnob(knob)->set(knobs, value);
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
  for (const KnobKey& key : kKnobKeys) pins.values_[key.name] = key.value(knobs);
  return pins;
}

}  // namespace sb
