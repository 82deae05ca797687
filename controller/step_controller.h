#pragma once
// `step`: the hierarchical step controller (architecture.md D4). The same velocity tests as slambooster
// (P, I, D, smooth surface, a correction) give a target level; it only becomes a signal: target below
// `precision_below_level` -> "more precision", above `approximation_above_level` -> "more approximation",
// else hold. Each signal moves one knob one level: approximation raises the knobs in importance order
// (csr, then icp, then pd0, each up to its maximum level), precision undoes the last such move. Moves towards
// approximation wait for the same hold as slambooster's; pose correction works as in slambooster.

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "controller/controller.h"
#include "controller/knob_ladder.h"
#include "controller/pose_corrector.h"
#include "controller/surface_detector.h"
#include "controller/velocity_signals.h"

namespace sb {

struct StepConfig {
  int bootstrapFrames = 14;
  PidParams pid;
  int approximationHoldFrames = 3;  // consecutive "more approximation" signals before a move
  int precisionBelowLevel = 1;      // target < this -> more precision
  int approximationAboveLevel = 1;  // target > this -> more approximation
  bool surfaceDetection = true;
  SurfaceParams surface;
  bool poseCorrection = true;
  CorrectionParams correction;
  int csrMaxLevel = 3, icpMaxLevel = 4, pd0MaxLevel = 3;  // highest level of each knob (ladder indices)
  int icpBaseLevel = 2;                                   // icp level at the most precise position (1e-5)
  KnobLadder ladder;

  // Section keys: bootstrap_frames, approximation_hold_frames, precision_below_level, approximation_above_level,
  // surface_detection, pose_correction, csr_max_level, icp_max_level, pd0_max_level, icp_base_level, and those
  // of PidParams, SurfaceParams, CorrectionParams and KnobLadder.
  void read(ConfigReader& reader);
  nlohmann::json toJson() const;  // every key read() reads, with its value
};

class StepController final : public Controller {
 public:
  StepController(std::string name, const StepConfig& config);
  const std::string& name() const override { return name_; }
  Knobs initialKnobs() const override { return knobsAt(0); }
  Decision decide(const Observation& observation) override;
  // Position 0 = most precise; each position one knob one level further (csr, then icp, then pd0).
  int positions() const { return static_cast<int>(moves_.size()) + 1; }
  Knobs knobsAt(int position) const;

 private:
  std::string name_;
  StepConfig config_;
  std::vector<int> moves_;  // knob index (0 csr, 1 icp, 2 pd0) raised by each position step
  VelocityHistory history_;
  PoseCorrector corrector_;
  int position_ = 0;
  int held_ = 0;
  size_t seen_ = 0;
};

}  // namespace sb
