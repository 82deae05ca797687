#include "pipeline/pipeline.h"

#include <cmath>

#include "core/error.h"
#include "pipeline/backend_factory.h"
#include "pipeline/cpu/cpu_backend.h"
#include "pipeline/icp_solve.h"

namespace sb {

Pipeline::Pipeline(const PipelineConfig& config, const Intrinsics& intrinsics, std::unique_ptr<ComputeBackend> backend)
    : config_(config), intrinsics_(intrinsics), backend_(std::move(backend)) {
  validateConfig(config_);
  if (!backend_) throw Error("Pipeline: no compute backend given");
  initialPose_ = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 3; ++i) initialPose_.translation()(i) = double(config_.initialPosition[i]) * config_.volumeSize;
  pose_ = initialPose_;
  referencePose_ = initialPose_;
  lastFinalPose_ = initialPose_;
  if (config_.movesVolume()) window_ = std::make_unique<VolumeWindow>(config_);
}

std::unique_ptr<Pipeline> Pipeline::create(const PipelineConfig& config, const Intrinsics& intrinsics, ThreadPool& pool) {
  return std::make_unique<Pipeline>(config, intrinsics, makeBackend(config, intrinsics, pool));
}

std::unique_ptr<Pipeline> Pipeline::createCpu(const PipelineConfig& config, const Intrinsics& intrinsics, ThreadPool& pool) {
  return std::make_unique<Pipeline>(config, intrinsics, std::make_unique<CpuBackend>(config, intrinsics, pool));
}

void Pipeline::checkInput(const DepthFrame& frame, double depthScale, const Knobs& knobs) const {
  validateKnobs(knobs);
  if (frame.depth.width() != intrinsics_.width || frame.depth.height() != intrinsics_.height)
    throw Error("frame " + std::to_string(frame.index) + " is " + std::to_string(frame.depth.width()) + "x" +
                std::to_string(frame.depth.height()) + " but the intrinsics say " + std::to_string(intrinsics_.width) +
                "x" + std::to_string(intrinsics_.height));
  if (!(depthScale > 0)) throw Error("depth scale must be positive (raw units per metre), got " + std::to_string(depthScale));
  const int minSide = std::min(intrinsics_.width, intrinsics_.height) / knobs.csr;
  if ((minSide >> (kPyramidLevels - 1)) < 2)
    throw Error("knob csr=" + std::to_string(knobs.csr) + " leaves a " + std::to_string(intrinsics_.width / knobs.csr) +
                "x" + std::to_string(intrinsics_.height / knobs.csr) + " image, too small for a 3-level pyramid");
}

FrameResult Pipeline::trackFrame(const DepthFrame& frame, double depthScale, const Knobs& knobs,
                                 const IcpStart& start) {
  if (awaitingFinish_)
    throw Error("Pipeline::trackFrame called twice without finishFrame (frame " + std::to_string(frameCount_) + ")");
  checkInput(frame, depthScale, knobs);
  FrameResult r;
  r.frame = frameCount_;
  r.timestamp = frame.timestamp;
  r.knobs = knobs;
  startPose_ = start.pose ? *start.pose : lastFinalPose_;
  holdBelowConditioning_ = start.holdBelowConditioning;
  prior_ = start.prior;
  track(frame, depthScale, r);
  awaitingFinish_ = true;
  return r;
}

void Pipeline::retrackFrame(const DepthFrame& frame, double depthScale, const Knobs& knobs, FrameResult& r) {
  if (!awaitingFinish_) throw Error("Pipeline::retrackFrame called without a preceding trackFrame");
  checkInput(frame, depthScale, knobs);
  if (!r.retracked) r.firstKnobs = r.knobs;
  r.retracked = true;
  r.knobs = knobs;
  r.trackingAttempted = false;
  r.tracked = false;
  r.residual = 0.0;
  r.inlierFraction = 0.0;
  r.pairAgreement = 0.0;
  r.modelCoverage = 0.0;
  r.icpLevelIterations = {};
  r.icpUpdateNorm = 0.0;
  r.quality = TrackingQuality{};
  track(frame, depthScale, r);  // from the same start pose as the first pass
}

void Pipeline::track(const DepthFrame& frame, double depthScale, FrameResult& r) {
  const Knobs& knobs = r.knobs;
  pose_ = lastFinalPose_;  // until ICP accepts a pose
  const bool bootstrap = frameCount_ < static_cast<size_t>(config_.bootstrapFrames);
  if (!bootstrap && frameCount_ % knobs.trackingRate != 0) {
    // Skipped by the tracking rate: nothing to preprocess (an untracked frame is not fused; a later trackFrom
    // or retrack preprocesses it then).
    preprocessedCsr_ = 0;
    r.T_camera_to_world = pose_;
    return;
  }
  backend_->preprocess(frame.depth, static_cast<float>(1.0 / depthScale), knobs.csr, r.times);
  preprocessedCsr_ = knobs.csr;
  if (!bootstrap && referenceCsr_ != 0) {
    const int wanted = referenceChosen_ ? referenceCsr_ : knobs.csr;
    if (referenceCsr_ != wanted || referenceStale_) {
      // The reference maps have the compute size unless one was chosen: raycast them again from the same pose.
      backend_->raycast(referencePose_.cast<float>(), wanted, r.times);
      referenceCsr_ = wanted;
      referenceStale_ = false;
    }
    r.trackingAttempted = true;
    r.tracked = runIcp(knobs, r);
  }
  r.T_camera_to_world = pose_;
}

TrackAttempt Pipeline::icp(const Knobs& knobs, const Eigen::Isometry3d& start, StageTimes& times,
                           std::array<int, 3>& levelIterations, const DepthNoiseModel* noise) {
  TrackAttempt a;
  a.start = start;
  Eigen::Isometry3d estimate = start;
  const Eigen::Isometry3f reference = referencePose_.cast<float>();
  TrackSums last{};
  int lastLevel = -1;
  for (int level = kPyramidLevels - 1; level >= 0; --level) {
    for (int i = 0; i < knobs.pyramidIterations[level]; ++i) {
      last = backend_->track(level, estimate.cast<float>(), reference, times);
      lastLevel = level;
      ++a.icpIterations;
      ++levelIterations[level];
      Twist x;
      if (!solveIcpUpdateHolding(last, estimate, holdBelowConditioning_, x, prior_ ? &*prior_ : nullptr)) break;
      a.icpUpdateNorm = x.norm();
      estimate = twistToTransform(x) * estimate;
      if (x.norm() < knobs.icpThreshold) break;
    }
  }
  const int width = (intrinsics_.width / knobs.csr) >> std::max(lastLevel, 0);
  const int height = (intrinsics_.height / knobs.csr) >> std::max(lastLevel, 0);
  const double inliers = last[28];
  a.inlierFraction = inliers / (double(width) * height);
  a.residual = inliers > 0 ? std::sqrt(last[0] / inliers) : 0.0;
  const double pairs = inliers + last[29] + last[30];
  a.pairAgreement = pairs > 0 ? inliers / pairs : 0.0;
  a.modelCoverage = pairs / (double(width) * height);
  if (noise && noise->on() && lastLevel >= 0) {
    if (const std::optional<PairCounts> counts = backend_->pairsInNoise(*noise, times))
      a.agreementInNoise = counts->agreement();
  }
  a.tracked = inliers > 0 && a.residual <= config_.trackedMaxResidual &&
              a.inlierFraction >= config_.trackedMinInliers && estimate.matrix().allFinite();
  if (lastLevel >= 0) {
    // Blocks of about qualityBlockPixels sensor pixels: the model's noise is correlated over a few voxels, so a
    // block must span a similar patch of the scene whatever the compute size.
    const int block = std::max(1, config_.qualityBlockPixels / (knobs.csr << lastLevel));
    const TrackSums blocks = backend_->blockSums(block, times);
    a.quality = trackingQuality(last, blocks, estimate, config_.constrainedMinConditioning);
  }
  a.T_camera_to_world = a.tracked ? estimate : start;
  return a;
}

bool Pipeline::runIcp(const Knobs& knobs, FrameResult& r) {
  const TrackAttempt a = icp(knobs, startPose_, r.times, r.icpLevelIterations);
  r.icpIterations += a.icpIterations;
  r.icpUpdateNorm = a.icpUpdateNorm;
  r.inlierFraction = a.inlierFraction;
  r.residual = a.residual;
  r.pairAgreement = a.pairAgreement;
  r.modelCoverage = a.modelCoverage;
  if (a.quality.known) r.quality = a.quality;
  pose_ = a.tracked ? a.T_camera_to_world : lastFinalPose_;  // a failed track keeps the previous final pose
  return a.tracked;
}

TrackAttempt Pipeline::trackFrom(const DepthFrame& frame, double depthScale, const Knobs& knobs,
                                 const Eigen::Isometry3d& start, FrameResult& r) {
  if (!awaitingFinish_) throw Error("Pipeline::trackFrom called without a preceding trackFrame");
  checkInput(frame, depthScale, knobs);
  if (knobs.csr != preprocessedCsr_) {
    backend_->preprocess(frame.depth, static_cast<float>(1.0 / depthScale), knobs.csr, r.times);
    preprocessedCsr_ = knobs.csr;
  }
  backend_->raycast(start.cast<float>(), knobs.csr, r.times);
  referencePose_ = start;
  referenceCsr_ = knobs.csr;
  referenceStale_ = false;
  std::array<int, 3> levelIterations{};
  const DepthNoiseModel noise = sensorNoise();
  return icp(knobs, start, r.times, levelIterations, &noise);
}

TrackAttempt Pipeline::trackOtherFrom(const DepthFrame& other, double depthScale, const Knobs& knobs,
                                      const Eigen::Isometry3d& start, const DepthNoiseModel& noise, FrameResult& r) {
  if (!awaitingFinish_) throw Error("Pipeline::trackOtherFrom called without a preceding trackFrame");
  checkInput(other, depthScale, knobs);
  backend_->preprocess(other.depth, static_cast<float>(1.0 / depthScale), knobs.csr, r.times);
  preprocessedCsr_ = 0;  // the backend no longer holds the frame in hand: its next trackFrom preprocesses it again
  backend_->raycast(start.cast<float>(), knobs.csr, r.times);
  referencePose_ = start;
  referenceCsr_ = knobs.csr;
  referenceStale_ = false;
  std::array<int, 3> levelIterations{};
  return icp(knobs, start, r.times, levelIterations, &noise);
}

void Pipeline::adoptAttempt(const TrackAttempt& a, FrameResult& r) {
  if (!awaitingFinish_) throw Error("Pipeline::adoptAttempt called without a preceding trackFrame");
  pose_ = a.T_camera_to_world;
  r.T_camera_to_world = pose_;
  r.trackingAttempted = true;
  r.tracked = a.tracked;
  r.residual = a.residual;
  r.inlierFraction = a.inlierFraction;
  r.pairAgreement = a.pairAgreement;
  r.modelCoverage = a.modelCoverage;
  r.icpUpdateNorm = a.icpUpdateNorm;
  r.quality = a.quality;
}

void Pipeline::discardTrack(FrameResult& r) {
  if (!awaitingFinish_) throw Error("Pipeline::discardTrack called without a preceding trackFrame");
  pose_ = lastFinalPose_;
  r.T_camera_to_world = pose_;
  r.tracked = false;
}

void Pipeline::finishFrame(FrameResult& r, const std::optional<Eigen::Isometry3d>& correctedPose,
                           const FrameOverrides& overrides) {
  if (!awaitingFinish_) throw Error("Pipeline::finishFrame called without a preceding trackFrame");
  if (overrides.referenceCsr && !validCsr(*overrides.referenceCsr))
    throw Error("Pipeline::finishFrame: reference compute size ratio " + std::to_string(*overrides.referenceCsr) +
                " is not 1, 2, 4 or 8");
  awaitingFinish_ = false;
  const Eigen::Isometry3d previous = lastFinalPose_;
  if (correctedPose) {
    pose_ = *correctedPose;
    r.poseOverridden = true;
  } else if (overrides.refinedPose && r.tracked) {
    pose_ = *overrides.refinedPose;
  }
  r.T_camera_to_world = pose_;
  const bool bootstrap = r.frame < static_cast<size_t>(config_.bootstrapFrames);
  const bool due = overrides.integrate ? *overrides.integrate : r.frame % r.knobs.integrationRate == 0;
  if (bootstrap || ((r.tracked || overrides.integrateUntracked) && due)) {
    backend_->integrate(pose_.cast<float>(), r.times);
    r.integrated = true;
    referenceStale_ = true;
  }
  const bool poseMoved = pose_.matrix() != referencePose_.matrix();
  const int referenceCsr = overrides.referenceCsr.value_or(r.knobs.csr);
  referenceChosen_ = overrides.referenceCsr.has_value();
  const bool keep = overrides.keepReference && !referenceStale_ && referenceCsr_ == referenceCsr;
  if (!keep && (referenceStale_ || poseMoved || referenceCsr_ != referenceCsr)) {
    backend_->raycast(pose_.cast<float>(), referenceCsr, r.times);
    referencePose_ = pose_;
    referenceCsr_ = referenceCsr;
    referenceStale_ = false;
  }
  r.velocity = (pose_.translation() - previous.translation()).norm();
  lastFinalPose_ = pose_;
  ++frameCount_;
  // The reference maps are in the world frame: they stay valid for the next frame's track across a shift.
  if (window_) window_->follow(pose_, *backend_);
}

FrameResult Pipeline::processFrame(const DepthFrame& frame, double depthScale, const Knobs& knobs) {
  FrameResult r = trackFrame(frame, depthScale, knobs);
  finishFrame(r);
  return r;
}

Image<uint8_t> Pipeline::renderModel(int csr) {
  StageTimes times;
  backend_->raycast(pose_.cast<float>(), csr, times);
  referencePose_ = pose_;
  referenceCsr_ = csr;
  referenceStale_ = false;
  return backend_->render(pose_.translation().cast<float>(), times);
}

Image<uint8_t> Pipeline::renderModel(const Eigen::Isometry3d& T_camera_to_world, int csr) {
  StageTimes times;
  backend_->raycast(T_camera_to_world.cast<float>(), csr, times);
  referenceStale_ = true;  // the maps no longer show referencePose_
  return backend_->render(T_camera_to_world.translation().cast<float>(), times);
}

}  // namespace sb
