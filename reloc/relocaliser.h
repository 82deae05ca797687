#pragma once
// Relocalisation from depth alone (issue 29): while tracking is good the relocaliser keeps keyframes (fern
// codes of views unlike the stored ones, keyframe_database.h); when the tracker is lost, each frame tries ICP
// against the model from a few start poses (the last good pose and the poses of the keyframes most like the
// frame) and a candidate is accepted only
//   - on the evidence that accepts a tracked frame: the pipeline's tracked tests (residual, inliers), a view
//     that constrains every motion (tracking quality), and most of the pairs the model predicts agreeing
//     (TrackAttempt::pairAgreement: a pose in the wrong place pairs the frame with surfaces it does not fit);
//   - and when it holds over `confirmFrames` consecutive frames: each next frame, tracked from the candidate's
//     pose, passes the same tests and moves no more than a camera can between two frames.
// A false relocalisation is worse than none: there is no fallback that accepts weaker evidence.
//
// Cost of a lost frame, bounded: at most 1 + candidates ICP runs (each a raycast and at most pd0+pd1+pd2 track
// passes at the relocaliser's compute size), or a single one while a candidate is being confirmed, none on a
// frame with too little depth; plus one fern code (fern_encoder.h) and one search of the keyframes.

#include <Eigen/Geometry>
#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/pipeline.h"
#include "reloc/keyframe_database.h"

namespace sb {

// The relocaliser's settings. Each default lives once, as a key of the pipeline config (pipeline/config.h:
// relocalise_*, keyframe_*; config/README.md): a default-constructed RelocaliserParams is the one made from
// PipelineConfig{} (tests/reloc/test_reloc_defaults.cpp checks that no default here repeats one there).
struct RelocaliserParams {
  RelocaliserParams() : RelocaliserParams(PipelineConfig{}) {}
  explicit RelocaliserParams(const PipelineConfig& c);

  int candidates;             // keyframes tried per lost frame (plus the last good pose)
  int confirmFrames;          // consecutive frames a candidate must hold (the first included)
  double minPairAgreement;    // of an attempt's pairs, [0, 1]
  // And at least the 90th percentile of the agreement of the last `agreementWindowFrames` good frames less this:
  // a view placed right agrees with the map as well as this sensor's tracked views of this scene did when they
  // were right (the percentile, not the median: the frames before a loss agree less and less). True
  // relocalisations held -0.007 to +0.06 of it (7-Scenes kidnaps: 0.87-0.90, relocalised at 0.88-0.93;
  // synthetic: 0.92-0.97, at 0.97-1.00), the aliased places of a symmetric corridor 0.028-0.10 below it.
  double agreementMargin;
  // The candidate's view must fix every motion at least this well (structure conditioning, tracking_quality.h),
  // more than tracking asks: a tracked frame has its last pose, a relocalised one nothing, and a view that
  // barely fixes a motion cannot say where along it the camera is (a corridor's blank end wall matched the other
  // end's at 0.00037-0.0012; true relocalisations held 0.0079-0.026).
  double minConditioning;
  double maxMotionM;          // metres between two confirming frames
  double maxRotationDeg;      // degrees between two confirming frames
  size_t keyframeCapacity;    // keyframes held (the oldest goes when full)
  double keyframeMinDissimilarity;  // a view unlike every keyframe by more than this becomes one
  size_t agreementWindowFrames = 300;  // good frames whose agreement sets the bar (not a config key)
};

// The agreement an attempt is judged on: within the sensor's noise at each pair's range when the pipeline
// counted it (TrackAttempt::agreementInNoise, pipeline/pair_noise.h), else tracking's pair agreement. The bar
// from the tracked frames (requiredAgreement) stays in tracking's measure (noteTracked is given
// FrameResult::pairAgreement), which within the noise is never higher: with the noise on, a kidnap's candidate is
// judged more leniently than with it off (the synthetic kidnaps of tests/tools/test_relocalisation_cli.cpp, 320x240:
// the same frame relocalised and the same ATE with it on as off; the noise is off by default).
inline double evidenceAgreement(const TrackAttempt& a) { return a.agreementInNoise.value_or(a.pairAgreement); }

// One ICP run of the frame in hand from a start pose (Pipeline::trackFrom, bound to the frame).
using TryPose = std::function<TrackAttempt(const Eigen::Isometry3d& start)>;

struct RelocaliseOutcome {
  bool accepted = false;              // relocalised: `attempt` is this frame's pose
  std::optional<TrackAttempt> attempt;  // accepted, or the candidate now being confirmed
  int tries = 0;                      // ICP runs this frame
  int confirmed = 0;                  // consecutive frames the pending candidate has held (0: none)
  std::string why;                    // in words, for the per-frame log
};

class Relocaliser {
 public:
  explicit Relocaliser(const RelocaliserParams& params);

  // Offers a view seen while tracking was good as a keyframe. True when it became one.
  bool harvest(const FernCode& code, const Eigen::Isometry3d& T_camera_to_world, size_t frame) {
    return keyframes_.harvest(code, T_camera_to_world, frame);
  }
  // One lost frame whose fern code is `code` (invalid when the frame has too little depth: then nothing is
  // tried and a pending candidate is dropped). `heldPose`: the last good pose.
  RelocaliseOutcome relocalise(const FernCode& code, const Eigen::Isometry3d& heldPose, const TryPose& tryPose);
  // The pair agreement of a frame tracked with good state (the level a relocalised view must reach).
  void noteTracked(double pairAgreement);
  // The agreement an attempt needs now: minPairAgreement, or the recent tracked 90th percentile less the margin
  // when that is higher (once 10 good frames are known).
  double requiredAgreement() const;
  // A kept map's keyframes (runtime/map_store.h), in its frame: searched like the ones harvested. Returns how
  // many were taken (codes of another size are not).
  size_t seed(const std::vector<Keyframe>& keyframes);
  // Whether each fresh search also tries the held pose (true by default). Off while localising in a kept
  // map: the held pose is in no frame of the store.
  void setTryHeldPose(bool tryIt) { tryHeldPose_ = tryIt; }
  // Each keyframe candidate is also tried moved by these metres along its view (its camera's +z), nearest
  // first: a robot restarted on a path it drove stands between two keyframes, nearer one of these than the
  // keyframe (ICP converges from a few tenths of a metre at most). None by default.
  void setViewOffsets(std::vector<double> offsetsM) { viewOffsetsM_ = std::move(offsetsM); }
  // Consecutive frames a candidate must hold from now on (a kept map asks more than a kidnap); >= 1.
  void setConfirmFrames(int frames) { params_.confirmFrames = frames < 1 ? 1 : frames; }
  // The conditioning a candidate's confirming frames need (each frame after the one that found it), from now on:
  // lower than minConditioning where something else fixes what the view leaves nearly free (a kept map's
  // candidate carried by the wheels, runtime/tracking_monitor.h); unset: minConditioning, as a found candidate.
  void setConfirmConditioning(std::optional<double> conditioning) { confirmConditioning_ = conditioning; }
  // Whether each fresh search's candidates (the held pose, the keyframes) are tried in an order rotated by one
  // each search: where each try may first have to move the volume, and only one move is allowed a frame
  // (runtime/map_store.h, placeFor), every candidate is reached in turn. Off by default; the best acceptable
  // attempt of a search does not depend on the order.
  void setRotateStarts(bool rotate) { rotateStarts_ = rotate; }
  // KeyframeDatabase::setMaxSpacing: keyframes also by distance (a map kept across runs).
  void setKeyframeSpacing(double metres) { keyframes_.setMaxSpacing(metres); }
  // Forgets a pending candidate (tracking went on without relocalisation).
  void reset() { pending_.reset(); confirmed_ = 0; }

  // The acceptance rule for one attempt (without the agreement over frames).
  bool acceptable(const TrackAttempt& attempt) const { return acceptable(attempt, params_.minConditioning); }
  const KeyframeDatabase& keyframes() const { return keyframes_; }
  const RelocaliserParams& params() const { return params_; }

 private:
  bool acceptable(const TrackAttempt& attempt, double minConditioning) const;

  RelocaliserParams params_;
  KeyframeDatabase keyframes_;
  std::optional<Eigen::Isometry3d> pending_;  // the candidate being confirmed: its pose at the last frame
  std::deque<double> tracked_;                // pair agreement of the last good frames (bounded)
  int confirmed_ = 0;
  bool tryHeldPose_ = true;
  bool rotateStarts_ = false;
  size_t freshSearches_ = 0;  // counts the searches while rotating
  std::vector<double> viewOffsetsM_;
  std::optional<double> confirmConditioning_;
};

}  // namespace sb
