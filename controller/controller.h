#pragma once
// The controller interface (architecture.md D4): after tracking each frame, a controller sees an Observation
// and returns a Decision: the knobs of the next frame, optionally a corrected pose for this frame (used by
// integration and raycast), a half-precision wish, and the triggers that fired (for the log).
//
// Lifecycle: create through the registry (controller/registry.h), ask initialKnobs() for frame 0, then call
// decide() once per frame in order, twice on a frame the controller asked to re-track (the second call
// carries the second pass's observation, retracked = true). A controller keeps whatever history it needs itself; it is not
// thread-safe (one SLAM thread owns it).

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/image.h"
#include "pipeline/knobs.h"
#include "pipeline/stages.h"
#include "pipeline/tracking_quality.h"

namespace sb {

struct Observation {
  size_t frame = 0;                // 0-based frame count of the run
  double timestamp = 0.0;          // seconds (sequence or capture time)
  Knobs knobs;                     // the knobs this frame ran with
  bool trackingAttempted = false;  // false in the pipeline's bootstrap frames and frames skipped by tr
  bool tracked = false;            // ICP result passed the residual and inlier tests
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();          // this frame's pose after tracking, volume frame
  Eigen::Isometry3d previousPose = Eigen::Isometry3d::Identity();  // the previous frame's final pose
  double velocity = 0.0;           // m/frame: |translation(pose) - translation(previousPose)|
  double rotationDeg = 0.0;        // degrees/frame: angle of rotation(previousPose)^-1 * rotation(pose)
  double residual = 0.0;           // m: RMS point-to-plane residual of the last ICP pass
  double inlierFraction = 0.0;     // ICP inliers / pixels
  std::array<int, 3> icpLevelIterations{};  // ICP iterations of the last pass per level: finest, mid, coarsest
  double icpUpdateNorm = 0.0;      // norm of the last ICP update (m and rad)
  TrackingQuality quality;         // conditioning of the ICP problem (pipeline/tracking_quality.h)
  bool retracked = false;          // this observation is of the frame's second pass (Decision::retrack)
  Knobs firstKnobs;                // when retracked: the knobs of the first pass
  StageTimes times;                // ms per stage of this frame so far (preprocessing and tracking)
  double previousComputationMs = 0.0;    // ms: the whole previous frame (0 before the first)
  std::optional<double> latestJoules;    // J per frame of the most recent frame whose energy is known
  const DepthRaw* depth = nullptr;       // the raw input frame (full size), borrowed for the call
  double depthScale = 1000.0;            // raw units per metre
  bool odometry = false;                 // the robot's wheel odometry gave this frame's motion (a robot driving)
};

// Trigger flags (bits of Decision::triggers), for the per-frame log and the activity plots.
enum Trigger : uint32_t {
  kTriggerBootstrap = 1u << 0,       // still in the controller's bootstrap: no approximation
  kTriggerIntegral = 1u << 1,        // I: window mean velocity above the threshold
  kTriggerDerivativeUp = 1u << 2,    // D: velocity non-decreasing over the D window
  kTriggerDerivativeDown = 1u << 3,  // D: velocity consistently decreasing
  kTriggerSurface = 1u << 4,         // smooth surface in view
  kTriggerCorrection = 1u << 5,      // pose replaced by constant-velocity extrapolation
  kTriggerHold = 1u << 6,            // a move towards approximation waits for the hold time
  kTriggerBudget = 1u << 7,          // budget/tc: the time or energy target was missed
  kTriggerRetrack = 1u << 8,         // adaptive: the frame was tracked again at a finer level
  kTriggerUnconstrained = 1u << 9,   // adaptive: the geometry did not fix every motion
  kTriggerDoubt = 1u << 10,          // adaptive: the tracking evidence was doubtful (see Decision::reason)
  kTriggerSkipIntegrate = 1u << 11,  // adaptive: the frame added too little to be integrated
};
// The names of the set bits, e.g. {"surface", "correction"}.
std::vector<std::string> triggerNames(uint32_t triggers);

struct Decision {
  Knobs next;                                       // knobs for the next frame
  std::optional<Eigen::Isometry3d> correctedPose;   // replaces this frame's pose when set
  // Refines a tracked frame's pose (e.g. fused with a motion prior): used unless correctedPose is set; not a
  // correction (frames.jsonl's `corrected` stays false).
  std::optional<Eigen::Isometry3d> refinedPose;
  bool halfPrecision = false;                       // wish: preprocessing and raycast in half precision
  uint32_t triggers = 0;                            // Trigger bits
  int level = -1;                                   // approximation level when the controller has one, else -1
  // Track this frame again with these knobs before finishing it; the runner then calls decide() once more
  // with the second pass's observation (retracked = true). Honoured once per frame.
  std::optional<Knobs> retrack;
  std::optional<bool> integrate;  // integrate this frame (if tracked) or not, instead of the knobs' rate
  bool keepReference = false;     // a frame not integrated keeps the reference maps (pipeline FrameOverrides)
  std::optional<int> referenceCsr;  // raycast the reference maps at this compute size ratio (FrameOverrides)
  // Where ICP starts on the next frame (e.g. a motion model's prediction); unset: the final pose of this one.
  std::optional<Eigen::Isometry3d> nextStartPose;
  // The next frame's ICP keeps the start pose along motions whose conditioning is below this (0: off).
  double nextHoldBelowConditioning = 0.0;
  std::string reason;             // why the knobs changed, in words, for the per-frame log ("" = no change)
};

// What a controller may borrow from the run it controls.
struct ControllerContext {
  Knobs baseKnobs;  // the pipeline config's knobs (what `fixed` without a preset runs)
};

class Controller {
 public:
  virtual ~Controller() = default;
  // The registry name, e.g. "fixed", "slambooster", "pid+surface".
  virtual const std::string& name() const = 0;
  // Knobs of the first frame this controller runs.
  virtual Knobs initialKnobs() const = 0;
  // Called once per frame, after tracking and before integration.
  virtual Decision decide(const Observation& observation) = 0;
};

}  // namespace sb
