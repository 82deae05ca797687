#pragma once
// Scripted observation sequences for controller tests: a camera that moves by a given step per frame,
// tracked from the 5th frame on (the pipeline's 4 bootstrap frames), with optional jumps and failures.

#include <vector>

#include "controller/controller.h"

namespace sb::test {

class ObservationScript {
 public:
  // `step`: the true motion per frame (world frame) used while velocity() is not overridden.
  explicit ObservationScript(const Eigen::Isometry3d& step = Eigen::Isometry3d::Identity()) : step_(step) {}

  // The next observation: the camera moved by `motion` from the previous final pose (`previousFinal`).
  // Frames < 4 are not tracked (pose unchanged). `tracked = false` keeps the previous pose, as the pipeline.
  Observation next(const Eigen::Isometry3d& motion, bool tracked = true) {
    Observation o;
    o.frame = frame_++;
    o.timestamp = o.frame / 30.0;
    o.previousPose = previousFinal_;
    o.trackingAttempted = o.frame >= 4;
    o.tracked = o.trackingAttempted && tracked;
    o.pose = o.tracked ? motion * previousFinal_ : previousFinal_;
    o.velocity = (o.pose.translation() - o.previousPose.translation()).norm();
    o.knobs = Knobs{};
    return o;
  }
  // A translation-only step of `metres` along x.
  Observation nextSpeed(double metres) {
    Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
    m.translation().x() = frame_ >= 4 ? metres : 0.0;
    return next(m);
  }
  // The caller reports the final pose (corrected or not).
  void finish(const Observation& o, const Decision& d) { previousFinal_ = d.correctedPose ? *d.correctedPose : o.pose; }

 private:
  Eigen::Isometry3d step_;
  Eigen::Isometry3d previousFinal_ = Eigen::Isometry3d::Identity();
  size_t frame_ = 0;
};

// Runs `controller` over per-frame speeds and returns the level of each decision.
inline std::vector<int> levelTrace(Controller& controller, const std::vector<double>& speeds,
                                   std::vector<uint32_t>* triggers = nullptr) {
  ObservationScript script;
  std::vector<int> levels;
  for (double v : speeds) {
    const Observation o = script.nextSpeed(v);
    const Decision d = controller.decide(o);
    script.finish(o, d);
    levels.push_back(d.level);
    if (triggers) triggers->push_back(d.triggers);
  }
  return levels;
}

}  // namespace sb::test
