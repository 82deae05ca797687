#pragma once
// The tracking state of a frame (issue 29; docs/tracking-state.md), for every controller, in frames.jsonl, the
// POSE message, STATUS, the summary, the report and the ROS bridge (one enum for all of them). A client acts on
// it: `lost` means "stop trusting the pose".
//   good         tracked, and the view constrains every motion (tracking quality)
//   weak         tracked, but some motion is fixed by noise rather than by the geometry (e.g. a blank wall), or
//                the tracked motion is one the platform cannot make (docs/odometry.md "Honest without it"), or
//                the view does not fit the map where it was tracked (its pair agreement far under the recent
//                good frames'; then not fused, and a run of them is lost)
//   lost         not tracked: the pose is the last good one (or the controller's bounded extrapolation for the
//                first lost_after_failed_frames - 1 failures); nothing is fused
//   relocalised  the relocaliser accepted a pose for this frame (reloc/relocaliser.h); the next frames track
//                from it
//   odometry     depth did not track, the pose follows the robot's odometry alone (docs/odometry.md), for a
//                bounded distance and time; nothing is fused
// Frames without a tracking attempt (the bootstrap, frames skipped by the tracking rate) carry the state of the
// last tracked frame (relocalised reads as good).

#include <optional>
#include <string_view>

namespace sb {

enum class TrackingState { good, weak, lost, relocalised, odometry };
constexpr int kTrackingStateCount = 5;

inline const char* trackingStateName(TrackingState s) {
  switch (s) {
    case TrackingState::weak: return "weak";
    case TrackingState::lost: return "lost";
    case TrackingState::relocalised: return "relocalised";
    case TrackingState::odometry: return "odometry";
    case TrackingState::good: break;
  }
  return "good";
}

// The state a name stands for (trackingStateName's inverse); nullopt for an unknown name.
inline std::optional<TrackingState> trackingStateFromName(std::string_view name) {
  for (int s = 0; s < kTrackingStateCount; ++s)
    if (name == trackingStateName(static_cast<TrackingState>(s))) return static_cast<TrackingState>(s);
  return std::nullopt;
}

// The frame's pose is an estimate (trajectory.tum, the ATE): every state but lost.
inline bool hasPoseEstimate(TrackingState s) { return s != TrackingState::lost; }

}  // namespace sb
