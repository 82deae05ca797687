#pragma once
// `slambooster`: the paper's controller (Algorithm 1; architecture.md D4). Per frame:
//   1. pose correction (when on): a velocity jump or failed track -> constant-velocity extrapolation;
//   2. v_t of the final pose enters the velocity history;
//   3. bootstrap: the first `bootstrap_frames` frames run level 0 (4 pipeline bootstrap frames + a 10-frame
//      velocity window in the original, so control decides frame 14 onwards);
//   4. target = P, I, D (velocity_signals.h), one level more precise for a smooth surface (when on) and for
//      a correction in this frame, clamped to [0, max_level];
//   5. asymmetric rate limits (rate_limiter.h) move the level; the coupled knobs of the level
//      (knob_ladder.h) are the next frame's knobs;
//   6. half precision is wished outside the bootstrap (when on).
// The parts are switchable for the incremental study: the registry names `pid`, `pid+surface`,
// `pid+surface+correction` and `slambooster` (all parts, half included) share the "slambooster" section.

#include <nlohmann/json_fwd.hpp>
#include <string>

#include "controller/controller.h"
#include "controller/knob_ladder.h"
#include "controller/pose_corrector.h"
#include "controller/rate_limiter.h"
#include "controller/surface_detector.h"
#include "controller/velocity_signals.h"

namespace sb {

struct SlamBoosterConfig {
  int bootstrapFrames = 14;  // frames [0, bootstrapFrames) run at level 0
  PidParams pid;
  RateLimitParams rate;
  bool surfaceDetection = true;
  SurfaceParams surface;
  bool poseCorrection = true;
  CorrectionParams correction;
  bool halfPrecision = true;
  KnobLadder ladder;

  // Section keys: bootstrap_frames, surface_detection, pose_correction, half_precision, and those of
  // PidParams, RateLimitParams, SurfaceParams, CorrectionParams and KnobLadder.
  void read(ConfigReader& reader);
  nlohmann::json toJson() const;  // every key read() reads, with its value
};

class SlamBoosterController final : public Controller {
 public:
  SlamBoosterController(std::string name, const SlamBoosterConfig& config);
  const std::string& name() const override { return name_; }
  Knobs initialKnobs() const override { return config_.ladder.coupled(0); }
  Decision decide(const Observation& observation) override;

  int level() const { return limiter_.level(); }

 private:
  std::string name_;
  SlamBoosterConfig config_;
  VelocityHistory history_;
  PoseCorrector corrector_;
  RateLimiter limiter_;
  size_t seen_ = 0;  // observations so far
};

}  // namespace sb
