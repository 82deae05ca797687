#pragma once
// The KinectFusion frame loop: preprocess -> track (coarse-to-fine ICP over 3 levels) -> integrate ->
// raycast, with knobs that may change between any two frames.
//
// A frame is processed in two calls so that a controller can look at the tracking result and replace the
// pose before the model is updated:
//   FrameResult r = pipeline.trackFrame(frame, depthScale, knobs);   // preprocess + track
//   ... controller looks at r, may decide on a corrected pose ...
//   pipeline.finishFrame(r, correctedPose);                          // integrate + raycast with that pose
// processFrame() does both without a correction. A controller that doubts a coarse result may have the same
// frame tracked again with other knobs before finishing it (retrackFrame), and may override the integration
// rate and keep the current reference maps for the next frame (FrameOverrides). Poses are T_camera_to_world in the volume frame (the
// cube [0, size]^3, metres); the first camera sits at initialPosition * size looking along +z. A moving volume
// (config volume_mode, volume_window.h) keeps that frame as the world's: poses never see a shift.

#include <Eigen/Geometry>
#include <memory>
#include <optional>

#include "core/intrinsics.h"
#include "core/thread_pool.h"
#include "drivers/frame_source.h"
#include "pipeline/backend.h"
#include "pipeline/config.h"
#include "pipeline/knobs.h"
#include "pipeline/pair_noise.h"
#include "pipeline/tracking_quality.h"
#include "pipeline/volume_window.h"

namespace sb {

struct FrameResult {
  size_t frame = 0;          // 0-based count of frames given to this pipeline
  double timestamp = 0.0;    // seconds, from the DepthFrame
  Knobs knobs;               // the knobs this frame ran with
  Eigen::Isometry3d T_camera_to_world = Eigen::Isometry3d::Identity();  // volume frame (after finishFrame: final)
  bool trackingAttempted = false;  // false in the bootstrap frames and on frames skipped by the tracking rate
  bool tracked = false;      // ICP converged to an acceptable pose (residual and inlier tests passed)
  bool poseOverridden = false;     // finishFrame was given a corrected pose
  bool integrated = false;   // the frame was fused into the volume
  double residual = 0.0;     // metres: RMS point-to-plane residual of the last ICP pass (0 when not attempted)
  double inlierFraction = 0.0;  // inliers of the last ICP pass / pixels at the compute size
  // Inliers of the last ICP pass / the pairs the model had a surface for (inliers, pairs too far, pairs with bad
  // normals): how much of what the model predicts the frame agrees with, [0, 1] (0 when not attempted).
  double pairAgreement = 0.0;
  // The pairs the model had a surface for / pixels at the last pass's size: how much of the view the model at the
  // tracked pose covers (0 when nothing was paired or not attempted). A view that agrees with none of a model
  // covering it (pair agreement 0) is the plainest evidence that the camera is not where it was tracked from.
  double modelCoverage = 0.0;
  int icpIterations = 0;     // ICP iterations run, all levels (both passes when retracked)
  std::array<int, 3> icpLevelIterations{};  // ICP iterations of the last pass per level: finest, mid, coarsest
  double icpUpdateNorm = 0.0;  // norm of the last ICP update (twist: m and rad), 0 when not attempted
  TrackingQuality quality;   // conditioning of the last ICP pass (tracking_quality.h)
  bool retracked = false;    // the frame was tracked a second time (retrackFrame); knobs are the second pass's
  Knobs firstKnobs;          // when retracked: the knobs of the first pass
  double velocity = 0.0;     // metres/frame: |translation - previous frame's translation| (after finishFrame)
  StageTimes times;          // ms per stage
};

// One ICP run of the frame in hand from a start pose (Pipeline::trackFrom): the evidence a relocaliser judges.
struct TrackAttempt {
  Eigen::Isometry3d start = Eigen::Isometry3d::Identity();              // where ICP started (volume frame)
  Eigen::Isometry3d T_camera_to_world = Eigen::Isometry3d::Identity();  // where it ended (start when it failed)
  bool tracked = false;        // passed the tracked tests (residual, inliers), like a tracked frame
  double residual = 0.0;       // metres, as FrameResult
  double inlierFraction = 0.0;
  double pairAgreement = 0.0;
  double modelCoverage = 0.0;  // as FrameResult
  // The share of the same pairs agreeing within the depth sensor's noise at each pixel's range
  // (pipeline/pair_noise.h), when the config gives the sensor's noise (depth_noise_disparity_px) and the backend
  // counts it: the evidence the relocaliser judges (reloc/relocaliser.h); unset: it judges pairAgreement.
  std::optional<double> agreementInNoise;
  int icpIterations = 0;
  double icpUpdateNorm = 0.0;  // of the last update
  TrackingQuality quality;
};

// Where ICP starts on a frame, and what it may move (Pipeline::trackFrame).
struct IcpStart {
  std::optional<Eigen::Isometry3d> pose;  // e.g. a motion model's prediction; unset: the previous final pose
  // Motions whose conditioning (tracking_quality.h) is below this keep the start pose: ICP does not move
  // along what the view leaves free (solveIcpUpdateHolding). 0: off, ICP moves along every motion.
  double holdBelowConditioning = 0.0;
  // A planar base's height and tilt, weighed in every ICP solve of the frame (icp_solve.h PlanarPrior); unset: none.
  std::optional<PlanarPrior> prior{};
};

// What a controller may change about how a frame is finished (Pipeline::finishFrame).
struct FrameOverrides {
  std::optional<bool> integrate;  // integrate this tracked frame or not, instead of the knobs' rate ir
  // Skip the raycast when the frame is not integrated: the next frame tracks against the current reference
  // maps (raycast from an earlier pose, which projective ICP handles like a larger motion).
  bool keepReference = false;
  // A tracked frame's pose refined by the controller (not a correction: FrameResult::poseOverridden stays false).
  std::optional<Eigen::Isometry3d> refinedPose;
  // Integrate (when due) although the frame was not tracked: its pose came from elsewhere (the odometry's).
  bool integrateUntracked = false;
  // Raycast the reference maps at this compute size ratio instead of the frame's (1, 2, 4 or 8), and track the
  // next frames against them whatever their compute size until a frame is finished without it. Projective ICP
  // pairs each input pixel with the reference pixel it projects to at any size: the input's resolution carries
  // the registration's accuracy, the reference's hardly (docs/odometry.md: a csr-1 input against csr-2 reference
  // maps tracked the drives as well as against csr-1 maps, at a quarter of the raycast).
  std::optional<int> referenceCsr;
};

class Pipeline {
 public:
  // `intrinsics`: of the full-size depth image. Throws sb::Error on an invalid config.
  Pipeline(const PipelineConfig& config, const Intrinsics& intrinsics, std::unique_ptr<ComputeBackend> backend);
  // A pipeline on the backend the config names (backend_factory.h: cpu, opencl or auto; the cpu backend runs
  // on `pool`, borrowed).
  static std::unique_ptr<Pipeline> create(const PipelineConfig& config, const Intrinsics& intrinsics,
                                          ThreadPool& pool = ThreadPool::global());
  // A pipeline on the CPU backend running on `pool` (borrowed; must outlive the pipeline).
  static std::unique_ptr<Pipeline> createCpu(const PipelineConfig& config, const Intrinsics& intrinsics,
                                             ThreadPool& pool = ThreadPool::global());
  // Of the full-size depth image.
  const Intrinsics& intrinsics() const { return intrinsics_; }

  // Preprocessing and tracking of one frame. `depthScale`: raw units per metre. Throws sb::Error on invalid
  // knobs or a frame whose size differs from the intrinsics, and when the previous frame was not finished.
  // ICP starts from `start.pose` when given, else from the previous frame's final pose; a failed track keeps
  // the previous frame's final pose either way.
  FrameResult trackFrame(const DepthFrame& frame, double depthScale, const Knobs& knobs, const IcpStart& start = {});
  // Tracks the frame of the last trackFrame again, from the same IcpStart, with other knobs (preprocessing
  // at their compute size included). Times add to `result`'s; its tracking fields are replaced. Throws
  // sb::Error like trackFrame, and when no frame awaits finishing.
  void retrackFrame(const DepthFrame& frame, double depthScale, const Knobs& knobs, FrameResult& result);
  // Integration (when due) and raycast with the tracked pose, or `correctedPose` when given. Completes `result`.
  void finishFrame(FrameResult& result, const std::optional<Eigen::Isometry3d>& correctedPose = std::nullopt,
                   const FrameOverrides& overrides = {});
  // Relocalisation (reloc/): tracks the frame in hand (after trackFrame, before finishFrame) from `start` against
  // the model raycast from `start`, with `knobs` (preprocessing again when their compute size differs from the
  // last). The frame's result and the pipeline's pose are unchanged; the stage times add to `result`'s. Throws
  // sb::Error like retrackFrame.
  TrackAttempt trackFrom(const DepthFrame& frame, double depthScale, const Knobs& knobs,
                         const Eigen::Isometry3d& start, FrameResult& result);
  // The same for a view other than the frame in hand (one seen earlier: a kept map's check of the path the wheels
  // drove, runtime/kept_map_history.h), with its agreement counted within `noise` (TrackAttempt::agreementInNoise;
  // unset when the backend does not count it). The frame in hand's preprocessing is dropped: its next trackFrom
  // redoes it; the frame's result and the pipeline's pose are unchanged. Throws sb::Error like trackFrom.
  TrackAttempt trackOtherFrom(const DepthFrame& other, double depthScale, const Knobs& knobs,
                              const Eigen::Isometry3d& start, const DepthNoiseModel& noise, FrameResult& result);
  // The depth sensor's noise as the config gives it (depth_noise_disparity_px; off when 0).
  DepthNoiseModel sensorNoise() const {
    return {config_.depthNoiseDisparityPx, config_.depthNoiseBaselineM, intrinsics_.fx};
  }
  // Makes an attempt (of this frame's trackFrom) the frame's tracking result: its pose becomes the frame's.
  void adoptAttempt(const TrackAttempt& attempt, FrameResult& result);
  // Discards the frame in hand's tracking: not tracked, the pose stays the previous frame's final pose.
  void discardTrack(FrameResult& result);
  // trackFrame + finishFrame.
  FrameResult processFrame(const DepthFrame& frame, double depthScale, const Knobs& knobs);

  const Eigen::Isometry3d& pose() const { return pose_; }
  // No bootstrap frames: no frame is fused at the initial pose before tracking (a run that starts localising in
  // a kept map, runtime/map_store.h: its volume holds the store's surface until it is localised). Before the
  // first frame.
  void skipBootstrap() { config_.bootstrapFrames = 0; }
  const Eigen::Isometry3d& initialPose() const { return initialPose_; }
  const PipelineConfig& config() const { return config_; }

  // A shaded image of the model seen from the current pose at full size / csr (raycast + render).
  Image<uint8_t> renderModel(int csr = 1);
  // The same from any camera pose (volume frame, camera looking along its +z, y down). The reference maps
  // then show that view, so the next frame raycasts them again from its own reference pose before tracking.
  Image<uint8_t> renderModel(const Eigen::Isometry3d& T_camera_to_world, int csr = 1);
  // The volume (2 * R^3 int16 pairs, layout in kernels/volume.h), valid until the next call.
  const int16_t* volumeData() { return backend_->volumeData(); }
  ComputeBackend& backend() { return *backend_; }
  // The moving volume's window (config volume_mode "moving"; it shifts at the end of finishFrame), or nullptr
  // for a fixed volume. Poses stay in the world frame either way.
  VolumeWindow* volumeWindow() { return window_.get(); }

 private:
  void checkInput(const DepthFrame& frame, double depthScale, const Knobs& knobs) const;
  void track(const DepthFrame& frame, double depthScale, FrameResult& result);
  bool runIcp(const Knobs& knobs, FrameResult& result);
  // ICP of the frame in hand at `knobs` from `start` against the current reference maps; `noise` (when on): also
  // TrackAttempt::agreementInNoise (a relocalisation attempt).
  TrackAttempt icp(const Knobs& knobs, const Eigen::Isometry3d& start, StageTimes& times,
                   std::array<int, 3>& levelIterations, const DepthNoiseModel* noise = nullptr);

  PipelineConfig config_;
  Intrinsics intrinsics_;
  std::unique_ptr<ComputeBackend> backend_;
  std::unique_ptr<VolumeWindow> window_;  // config_.movesVolume()
  Eigen::Isometry3d initialPose_;
  Eigen::Isometry3d pose_;          // latest camera pose (volume frame)
  Eigen::Isometry3d referencePose_;  // pose of the last raycast
  Eigen::Isometry3d lastFinalPose_;  // pose at the end of the previous frame
  Eigen::Isometry3d startPose_;      // where ICP starts for the frame in hand (trackFrame and retrackFrame)
  double holdBelowConditioning_ = 0.0;  // IcpStart's, for the frame in hand
  std::optional<PlanarPrior> prior_;    // IcpStart's, for the frame in hand
  int referenceCsr_ = 0;            // csr of the last raycast (0 = none yet)
  bool referenceChosen_ = false;    // that csr was FrameOverrides::referenceCsr: frames of any csr track against it
  int preprocessedCsr_ = 0;         // csr of the last preprocess
  bool referenceStale_ = false;     // the volume changed since the last raycast
  size_t frameCount_ = 0;
  bool awaitingFinish_ = false;
};

}  // namespace sb
