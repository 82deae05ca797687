#pragma once
// Drives an AdaptiveController the way SlamRunner does, for the adaptive tests: hand-made observations, the
// controller's knobs fed back, a re-track answered by a second observation of the same frame.

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "controller/adaptive_controller.h"
#include "controller/registry.h"
#include "tests/controller/observation_script.h"

namespace sb::test::adaptive {

using sb::AdaptiveController;
using sb::Decision;
using sb::Observation;

inline sb::AdaptiveConfig config(const char* json = "{}") {
  return sb::readControllerSettings<sb::AdaptiveConfig>(nlohmann::json::parse(json), "test");
}

inline Eigen::Isometry3d moveX(double metres) {
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  m.translation().x() = metres;
  return m;
}

// Drives a controller the way SlamRunner does: the observation carries the knobs the controller chose, a
// re-track request is answered by `second` (the finer pass's observation of the same frame).
struct Driver {
  explicit Driver(AdaptiveController& controller) : c(controller), knobs(controller.initialKnobs()) {}
  AdaptiveController& c;
  sb::test::ObservationScript script;
  sb::Knobs knobs;

  bool odometry = false;  // the frames carry the robot's odometry

  Observation observe(const Eigen::Isometry3d& motion, bool tracked = true) {
    Observation o = script.next(motion, tracked);
    o.knobs = knobs;
    o.odometry = odometry;
    o.icpLevelIterations = {1, 1, 1};
    o.inlierFraction = 0.6;
    if (o.trackingAttempted) o.quality = {true, 0.1, 0.1, sb::WeakDirection::tx, true};
    return o;
  }
  Decision finish(const Observation& o, Decision d) {
    script.finish(o, d);
    knobs = d.next;
    return d;
  }
  // One frame without re-track (REQUIREs that none is asked).
  Decision step(const Eigen::Isometry3d& motion, bool tracked = true) {
    const Observation o = observe(motion, tracked);
    const Decision d = c.decide(o);
    REQUIRE_FALSE(d.retrack);
    return finish(o, d);
  }
  // 12 tracked frames at 0.01 m/frame: with bootstrap_frames 0 and relax_frames 1, the coarsest level.
  void reachCoarsest() {
    for (int i = 0; i < 12; ++i) step(moveX(0.01));
    REQUIRE(c.level() == 3);
  }
  // The re-track that `d` asked for after `first`: the same frame at the finer knobs.
  static Observation retrackOf(const Observation& first, const Decision& d) {
    REQUIRE(d.retrack);
    Observation second = first;
    second.retracked = true;
    second.firstKnobs = first.knobs;
    second.knobs = *d.retrack;
    return second;
  }
};

}  // namespace sb::test::adaptive
