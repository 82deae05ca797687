#pragma once
// Tracking state and recovery for every controller (issue 29; tracking_state.h). The runner calls it on each
// frame:
//   trackFrame -> [recovering: the plain track is discarded] -> controller -> resolve() -> finishFrame -> after()
// Failed tracks in a row up to lost_after_failed_frames keep the controller's handling (its bounded
// extrapolation); from then on plain tracking is not trusted (a track from a stale pose after a kidnap can pass
// the residual and inlier tests in the wrong place): the pose is held, nothing is fused, and each frame the
// relocaliser (reloc/relocaliser.h) tries candidate poses until one is confirmed over consecutive frames.
// While tracking is good the frames feed the relocaliser's keyframes.

#include <cstddef>
#include <string>

#include "drivers/frame_source.h"
#include "pipeline/pipeline.h"
#include "reloc/fern_encoder.h"
#include "reloc/relocaliser.h"
#include "runtime/frame_record.h"

namespace sb {

class TrackingMonitor {
 public:
  explicit TrackingMonitor(const PipelineConfig& config);

  // Plain tracking is not trusted on the next frame (the frame's track is to be discarded).
  bool recovering() const { return recovering_; }
  // After the controller's decision on the frame in hand (rec.result, rec.decision): relocalises when
  // recovering, sets rec.state and rec.relocalisation, and overrides what a lost or relocalised frame may do
  // (no correction, no fusion, the next ICP from the held or relocalised pose).
  void resolve(Pipeline& pipeline, const DepthFrame& frame, double depthScale, FrameRecord& rec);
  // After finishFrame: a good frame is offered to the keyframe database.
  void after(const DepthFrame& frame, double depthScale, FrameRecord& rec);

  const Relocaliser& relocaliser() const { return relocaliser_; }

 private:
  PipelineConfig config_;
  FernEncoder encoder_;
  Relocaliser relocaliser_;
  int failedInARow_ = 0;
  bool recovering_ = false;
  TrackingState last_ = TrackingState::good;  // of the last frame with a tracking attempt
};

}  // namespace sb
