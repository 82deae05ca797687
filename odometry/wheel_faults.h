#pragma once
// When the wheels and the view disagree (issue 52; docs/wheel-faults.md): a fault of the base (a stall
// with spinning wheels, a wheel slip, wrong wheels) or of the view (a runaway, a robot carried elsewhere) is a
// disagreement that lasts, and one frame's physics cannot decide it. The map built before the disagreement is
// the referee: while the two disagree nothing is fused into it, and the evidence of a window of frames decides
//   - the view holds the map (it tracks with the agreement of the frames before) while the wheels report
//     another motion: the wheels are at fault (`slipping`); the pose follows the view, the wheels are not used
//     until their steps agree with the view's again;
//   - the view does not fit the map near the wheels' pose (its agreement falls, or it fails to track while
//     seeing what the map holds): the place is wrong (`kidnapped`, or a view that ran away); the pose follows
//     the wheels only within the dead-reckoning budget, nothing is fused, and the relocaliser searches the
//     whole map, where a candidate the view confirms wins over the wheels.
// Until one side has the evidence the dispute is `disputed` and no pose is `good`.

#include <Eigen/Geometry>
#include <deque>
#include <optional>
#include <string>

namespace sb::odometry {

enum class WheelFault { none, disputed, slipping, kidnapped };
const char* wheelFaultName(WheelFault fault);  // "none", "disputed", "slipping", "kidnapped"

// The map's agreement of the recent frames the view fixed without dispute: what a view that holds the map
// shows. A frame holds the map when its pair agreement (the share of the model's pairs it agrees with) is at
// least a fraction of their median. The agreement moves with the motion (a standing camera agrees with nearly
// all of a model it built itself, a driving one with 0.6-0.8 of it) but a view elsewhere agrees with a small
// part (a robot carried 9 m back along a corridor: 0.1-0.45 where its frames had 0.75-0.9).
class MapAgreement {
 public:
  explicit MapAgreement(double fraction) : fraction_(fraction) {}
  void add(double pairAgreement);
  // No history yet: every frame holds.
  bool holds(double pairAgreement) const;
  double floor() const;  // the agreement a frame must reach (0 without history)
  bool known() const { return !recent_.empty(); }
  // How much of the view the model covers (FrameResult::modelCoverage: the pairs the model had a surface for, per
  // pixel) on the recent undisputed frames. A view that fails to fit a model covering as much of
  // it as usual (at least kCoveredFraction of the recent median) is evidence that the camera is elsewhere: the
  // map at the wheels' pose is whole and the view does not match it. One that fails on a model that covers less
  // (a stretch the volume has not mapped yet, the far side of a U-turn: the coverage falls frame after frame as
  // the robot drives into it, 0.55 -> 0.3 -> 0.1 on a held-out drive) says nothing of where the camera is.
  void addCoverage(double coverage);
  bool covered(double coverage) const;
  // A view the map contradicts: it fails to hold the map, and the model covers enough of it for that to say the
  // camera is elsewhere: as much of the view as usual, or a model of which the pairs the view disagrees with alone
  // cover kContradictedFraction of what the model usually covers. The second is a model covering less than usual
  // and the view agreeing with almost none of it (a robot carried back along its path mid-turn and set down: the
  // model at the wheels' pose covered 0.57-0.72 of the view against 0.97 before, the view agreed with none of it,
  // and for 30 frames that was no evidence); a right pose over a model it sees only in part agrees with most of that
  // part. One the map does not contradict (it holds the map, or the model covers less of it: a part of the map seen
  // only from afar, or not at all) may be fused after a blind spell.
  bool contradicted(double pairAgreement, double coverage) const;
  bool uncontradicted(double pairAgreement, double coverage) const { return !contradicted(pairAgreement, coverage); }
  static constexpr double kCoveredFraction = 0.8;
  static constexpr double kContradictedFraction = 0.5;

 private:
  static constexpr size_t kFrames = 90;  // the recent undisputed frames (3 s at 30 Hz)
  double fraction_;
  std::deque<double> recent_, coverage_;
};

// The view's corrections of the wheels' turn summed over the last second. One frame's gate (slip_sigmas of the
// step's noise, at least slip_floor_m as radians: 1.7 degrees) lets wrong wheels through whose error per frame is
// under it but always the same: a gyro biased by 20 deg/s turns each 33 ms step 0.67 degrees off, and fused frame
// after frame the heading drifted 5 degrees in 10 s (a held-out drive: `good` frames 0.9 m off on the way back).
// Summed over n frames the floor grows as sqrt(n), as independent errors do: over a second at 30 Hz 9.4 degrees,
// which a constant error of 9 deg/s passes. What a base's wheels get wrong legitimately stays under it: a turn scale
// off by 5% at 90 deg/s (4.5 degrees in the second), a latency's lag at the start of a turn (its rate times the
// latency in all: 2.4 degrees at 60 deg/s and 40 ms), a mount tilted 2 degrees through a turn of 60 degrees (2
// degrees). A window of the 0.3 s decision time with the floor unscaled took a U-turn's 1.6 degrees for wrong
// wheels, and the view alone then lost the turn. A sum beyond the gate is evidence only on a frame that still
// corrects the wheels as the window does on average (a fault that has ended leaves its sum for a second, its frames
// do not). The turn only: summed, the translation's corrections also took a stall whose wheels read 0.6 m/s (2 cm a
// frame, under the 3 cm floor) for slipping wheels, and with the wheels out the view alone slid 0.3 m where the
// robot drove on along a motion it did not fix (a held-out drive, `adaptive`: 2.9 -> 25 cm); a stall has its own
// evidence (a view that stands still).
class TurnCorrections {
 public:
  explicit TurnCorrections(double windowS = 1.0) : windowS_(windowS) {}
  // A frame at `stamp` whose view turned the wheels' prediction by `rotation` (a rotation vector in the world
  // frame, radians), the step's turn noise `sigmaRad`. Returns why the corrections summed over the window (at least
  // kMinFrames of them) are beyond `sigmas` times their noise and the floor (one frame's `floorRad` times the square
  // root of the frames), or "".
  std::string add(double stamp, const Eigen::Vector3d& rotation, double sigmaRad, double sigmas, double floorRad);
  void clear() { frames_.clear(); }

 private:
  struct Frame {
    double stamp;
    Eigen::Vector3d rotation;
    double variance;
  };
  static constexpr size_t kMinFrames = 3;
  double windowS_;
  std::deque<Frame> frames_;
};

// The evidence of a disagreement, frame by frame, and the verdict.
class FaultWatch {
 public:
  // `decideS`: how long a disagreement must last before it is decided (the evidence of that many seconds of
  // frames, at least kMinFrames of them); `calmS`: how long the wheels' steps must agree with the view again
  // before a fault ends.
  FaultWatch(double decideS, double calmS) : decideS_(decideS), calmS_(calmS) {}

  WheelFault fault() const { return fault_; }
  // A frame at `stamp` where the view holds the map but the wheels' step contradicts it.
  void wheelsContradicted(double stamp);
  // A frame where the view does not fit the map near the wheels' pose (poor agreement, or no track while the
  // map was in view). Such frames for the decision time (at least kMinFrames, more than those against the wheels)
  // make it `kidnapped`: the robot is elsewhere. Not the dead-reckoning budget: a robot set down behind where it
  // was picked up drives on its wheels' pose into what the map does not hold yet, the evidence stops there, and a
  // dispute left to the budget was dropped and the view fused at the wheels' pose (a held-out drive: 669 `good`
  // frames 8 m off; decided by the window, relocalised 0.9 s after the set-down).
  void viewContradicted(double stamp);
  // The dead reckoning ran out of its budget during a dispute whose evidence is mostly of the view not fitting
  // the map near the wheels' pose, before the decision time: the robot is elsewhere (kidnapped; true). A view that
  // merely failed (a covered lens, a blank wall) is not that evidence.
  bool concludeKidnapped();
  // A frame where the view's correction of the wheels' prediction (`correctionM`, along the motions it fixes)
  // breaks the body's inertia: one such frame is the view jumping (it is discarded), but a correction that keeps
  // growing frame after frame is the wheels running away from a view that stays put (a stall: the view, tracked
  // from the wheels' prediction each frame, finds the pose 3, 7, 10 cm back). True when it has grown on
  // kMinFrames frames in a row to kGrowth times its first: the view is right. A dispute opens either way.
  // The frames must follow one another: a frame between them whose view was discarded as a motion the platform
  // cannot make, or failed to track (`interrupt`), ends the run (a held-out U-turn: corrections of 0.52 and 0.56 m
  // eight frames apart, the view swinging 20 m/s in between, were taken for a stall's growth and the view stood).
  // And the run starts only where the view is `withinReach` of the previous pose (no farther than the body's speed
  // carries it in the frame, plus the slip floor): a stall's view stops where the robot stood, a look-alike's lands
  // ahead (a held-out U-turn: the view 0.46 m from the last pose in one frame, then held there while its corrections
  // of the wheels rose from a few centimetres to 0.18 m, was taken for a stall and the pose jumped 0.26 m).
  bool diverging(double stamp, double correctionM, bool withinReach = true);
  // A frame where the view breaks the body's inertia by correcting the wheels' prediction by `correction` (the
  // camera centre's offset and the turn from the wheels' pose to the view's, world frame) without it growing: one such frame is the view jumping, but
  // the same correction frame after frame is the view moving exactly as the wheels do from a pose the map puts
  // elsewhere (the way back meeting the way out's map, offset by the drift between: a held-out U-turn, the view
  // correcting the wheels by 0.05 m on every frame for 3.5 s, each discarded as a jump, until the dispute was
  // taken for a kidnap). A look-alike or a runaway does not hold one correction while the robot drives: its
  // correction moves with every step. True when the correction has stayed within `toleranceM` (the view's noise
  // plus the step's) and kSteadyDeg of the last on frames in a row for the decision time, at least kMinFrames: the
  // view's pose stands. The run starts only where the correction is `withinReach` (as far as the wheels' pose may
  // be off the map: the relocaliser's tolerance, odometry_config.h).
  bool steady(double stamp, const Eigen::Isometry3d& correction, double toleranceM, bool withinReach);
  // The frames in a row end too: agreement (`agreed`) counts frames in a row, and a frame between them whose view
  // was discarded, or failed, did not agree (a held-out drive with wheels reading zero: agree, a view discarded as
  // a motion the platform cannot make, agree, agree, and the dispute ended on a `good` frame 0.62 m off).
  void interrupt() {
    rising_ = 0;
    calm_ = 0;
    steady_.reset();
  }
  // A frame where the two agree (the view holds the map and the wheels' step agrees with it).
  void agreed(double stamp);
  // A dispute still undecided with no evidence for either side for kStaleDecisions times the decision time (the
  // view fails to track where the map holds too little to judge by: the far side of a U-turn) is dropped: nothing
  // can decide it, and a map starved of every frame the wheels carry would never let the view track again.
  void expire(double stamp);
  // A dispute is open but neither side has evidence yet (one frame's inertia opened it): the frames the wheels
  // carry may still feed a map the view cannot track against, as without a dispute.
  bool unsupported() const { return fault_ == WheelFault::disputed && wheelsAgainst_ == 0 && viewAgainst_ == 0; }
  // The relocaliser placed the camera, or the run starts over: no dispute.
  void reset();
  // Why the state is what it is, for frames.jsonl ("" when none).
  const std::string& why() const { return why_; }

 private:
  static constexpr int kMinFrames = 3;
  static constexpr double kStaleDecisions = 3.0;
  double lastEvidence_ = 0.0;  // the stamp of the dispute's last frame of evidence (or its opening)
  void begin(double stamp);

  double decideS_, calmS_;
  WheelFault fault_ = WheelFault::none;
  double since_ = 0.0;       // the dispute's (or the calm's) first frame
  int wheelsAgainst_ = 0;    // frames of the dispute where the view held the map against the wheels
  int viewAgainst_ = 0;      // ... where the view did not fit the map
  int calm_ = 0;             // frames in a row of agreement since the last contradiction
  static constexpr double kGrowth = 2.5;
  int rising_ = 0;           // frames in a row whose inertia-breaking correction grew
  double firstCorrectionM_ = 0.0, lastCorrectionM_ = 0.0;
  double calmSince_ = 0.0;
  static constexpr double kSteadyDeg = 0.5;
  std::optional<Eigen::Isometry3d> steady_;  // the first correction of a steady run
  double steadySince_ = 0.0;                 // the run's first frame
  int steadyFrames_ = 0;
  std::string why_;
};

}  // namespace sb::odometry
