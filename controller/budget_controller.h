#pragma once
// `budget` (beyond the paper): the user sets a target computation time per frame (ms) or energy per frame
// (J); the controller runs the least approximation that meets it. It learns the cost of each coupled level
// online (exponential moving average of the measured cost of frames run at that level) and picks the lowest
// level whose estimate fits the target (a level never measured counts as fitting once its more approximate
// neighbour fits with `margin` to spare, so it is probed; estimates older than `reprobe_frames` are
// forgotten). Smooth surfaces and pose corrections still raise precision by one level each, and moves
// towards approximation follow slambooster's rate limits, so the guards win over the budget.

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "controller/controller.h"
#include "controller/knob_ladder.h"
#include "controller/pose_corrector.h"
#include "controller/rate_limiter.h"
#include "controller/surface_detector.h"

namespace sb {

struct BudgetConfig {
  double targetFrameMs = 0.0;   // ms of computation per frame (0 = not used)
  double targetJoules = 0.0;    // J per frame (0 = not used); exactly one target must be set
  double emaAlpha = 0.3;        // weight of the newest measurement
  double margin = 0.1;          // a lower level is probed when the current one is below (1 - margin) * target
  int reprobeFrames = 150;      // estimates not refreshed for this many frames are forgotten
  int bootstrapFrames = 14;
  RateLimitParams rate;
  bool surfaceDetection = true;
  SurfaceParams surface;
  bool poseCorrection = true;
  CorrectionParams correction;
  KnobLadder ladder;

  // Section keys: target_frame_ms, target_joules_per_frame, ema_alpha, margin, reprobe_frames, bootstrap_frames,
  // surface_detection, pose_correction, and those of RateLimitParams, SurfaceParams, CorrectionParams and
  // KnobLadder. Calls reader.finish(), then refuses settings with no target or two.
  void read(ConfigReader& reader);
  nlohmann::json toJson() const;  // every key read() reads, with its value
};

class BudgetController final : public Controller {
 public:
  BudgetController(std::string name, const BudgetConfig& config);
  const std::string& name() const override { return name_; }
  Knobs initialKnobs() const override { return config_.ladder.coupled(0); }
  Decision decide(const Observation& observation) override;
  // The current cost estimate of `level` (negative when unknown).
  double estimate(int level) const { return estimate_[static_cast<size_t>(level)]; }

 private:
  std::string name_;
  BudgetConfig config_;
  PoseCorrector corrector_;
  RateLimiter limiter_;
  std::vector<double> estimate_;     // per level, < 0 = unknown
  std::vector<size_t> measuredAt_;   // frame of the last update per level
  int previousLevel_ = 0;            // the level the observed frame ran at
  size_t seen_ = 0;
};

}  // namespace sb
