#pragma once
// The integration rate as a knob (issue 21): a tracked frame is fused into the model when it brings something
// new, i.e. when the camera moved or turned enough since the last fused frame, or after a bounded number of
// frames in any case (new noise samples). While exploring or moving fast every frame qualifies. A frame whose
// pose was corrected or doubted is never fused (the map stays clean), and a frame that is not fused keeps the
// reference maps of the last fused one, so the motion thresholds also bound how stale the reference gets.

#include <Eigen/Geometry>

#include "core/config_reader.h"

namespace sb {

struct IntegrationParams {
  double translationM = 0.04;  // m moved since the last fused frame that makes a frame worth fusing
  // The same while the robot's odometry drives the frames: a robot drives 3-4 cm per frame, and a frame not fused
  // is tracked against the last fused frame's reference maps, which projective ICP pairs with from any nearby
  // pose (a camera driving forward sees less than the reference 0.2 m behind it did). docs/odometry.md: at csr 1,
  // 0.2 m tracked five drives as well as DEFAULT, 0.3 m worse on 6 of 7.
  double translationWithOdometryM = 0.2;
  double rotationDeg = 4.0;    // degrees turned since the last fused frame that makes a frame worth fusing
  static constexpr int kMaxGap = 1000;
  int maxGapFrames = 8;        // a tracked frame is fused at least every this many frames

  // Keys: integrate_translation_m, integrate_translation_m_with_odometry, integrate_rotation_deg,
  // integrate_max_gap_frames.
  void read(ConfigReader& reader);
  void toJson(nlohmann::json& section) const;  // adds the same keys with their values
};

class IntegrationGate {
 public:
  explicit IntegrationGate(const IntegrationParams& params) : params_(params) {}
  // Whether the frame with final pose `pose` should be fused; `eligible`: tracked and its pose kept;
  // `odometry`: the robot's odometry drives the frame. Remembers the pose of the fused frames.
  bool decide(const Eigen::Isometry3d& pose, bool eligible, bool odometry = false);
  // A frame with no decision (skipped by the tracking rate): it counts towards the max gap all the same.
  void skipped() { ++sinceFused_; }
  // The next decision fuses any eligible frame (after bootstrap, a level change, ...).
  void reset() { fusedAny_ = false; }

 private:
  IntegrationParams params_;
  Eigen::Isometry3d lastFused_ = Eigen::Isometry3d::Identity();
  bool fusedAny_ = false;
  int sinceFused_ = 0;  // frames since the last fused one
};

}  // namespace sb
