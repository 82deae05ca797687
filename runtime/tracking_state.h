#pragma once
// The tracking state of a frame (issue 29), for every controller, in frames.jsonl, the POSE message, the
// summary and the report. A client acts on it: `lost` means "stop trusting the pose".
//   good         tracked, and the view constrains every motion (tracking quality)
//   weak         tracked, but some motion is fixed by noise rather than by the geometry (e.g. a blank wall)
//   lost         not tracked: the pose is the last good one (or the controller's bounded extrapolation for the
//                first lost_after_failed_frames - 1 failures); nothing is fused
//   relocalised  the relocaliser accepted a pose for this frame (reloc/relocaliser.h); the next frames track
//                from it
// Frames without a tracking attempt (the bootstrap, frames skipped by the tracking rate) carry the state of the
// last tracked frame (relocalised reads as good).

namespace sb {

enum class TrackingState { good, weak, lost, relocalised };
constexpr int kTrackingStateCount = 4;

inline const char* trackingStateName(TrackingState s) {
  switch (s) {
    case TrackingState::weak: return "weak";
    case TrackingState::lost: return "lost";
    case TrackingState::relocalised: return "relocalised";
    case TrackingState::good: break;
  }
  return "good";
}

}  // namespace sb
