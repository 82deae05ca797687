#pragma once
// Knobs pinned over the controller's choice (the daemon's ?CONTROL, runtime/slam_runner.h): a partial set of
// (knob, value) pairs, validated when set, applied to whatever the controller decides for each frame. Knob
// names: pinnableKnobs() (pipeline/knobs.h).

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pipeline/knobs.h"

namespace sb {


class KnobPins {
 public:
  // Pins `knob` to `value`. Throws sb::Error naming the knob, the value and what is allowed (nothing
  // changes).
  void pin(const std::string& knob, double value);
  // Unpins `knob`, or every knob for "all". Throws sb::Error for an unknown name.
  void unpin(const std::string& knob);

  bool empty() const { return values_.empty(); }
  // `knobs` with the pinned values in place.
  Knobs apply(Knobs knobs) const;
  std::vector<std::string> names() const;
  nlohmann::json toJson() const;
  // Every knob pinned to `knobs` (validated; throws sb::Error naming the problem).
  static KnobPins all(const Knobs& knobs);

 private:
  std::map<std::string, double> values_;
};

}  // namespace sb
