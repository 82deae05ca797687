#include "runtime/frame_log_sink.h"

#include <Eigen/Geometry>

#include "core/frame_log_fields.h"
#include "core/pose_fields.h"
#include "pipeline/knob_fields.h"

namespace sb {

PoseFields poseFieldsOf(const FrameRecord& rec) {
  const FrameResult& r = rec.result;
  PoseFields p;
  p.frame = r.frame;
  p.timestamp = r.timestamp;
  // The final pose, T_camera_to_world in the volume frame (metres; quaternion qx, qy, qz, qw, TUM order): what
  // trajectory.tum records, and for a lost frame the pose it holds.
  const Eigen::Vector3d t = r.T_camera_to_world.translation();
  const Eigen::Quaterniond q(r.T_camera_to_world.rotation());
  p.position = {t.x(), t.y(), t.z()};
  p.quaternion = {q.x(), q.y(), q.z(), q.w()};
  p.tracked = r.tracked;
  p.corrected = r.poseOverridden;
  p.state = rec.state;
  p.velocityMPerFrame = r.velocity;
  if (r.quality.known) {
    p.conditioning = r.quality.conditioning;
    p.weakestMotion = weakDirectionName(r.quality.weakest);
    p.constrained = r.quality.constrained;
  }
  p.odometry = rec.odometry.available;
  p.odometryDriftM = rec.odometry.driftM;
  if (rec.odometry.fault != odometry::WheelFault::none) p.odometryFault = odometry::wheelFaultName(rec.odometry.fault);
  if (rec.keptMap != KeptMap::none) p.keptMap = keptMapName(rec.keptMap);
  return p;
}

KnobFields knobFieldsOf(const FrameRecord& rec) {
  KnobFields k;
  k.frame = rec.result.frame;
  k.controller = rec.controller;
  k.computationMs = rec.result.times.computationMs();
  k.knobs = rec.result.knobs;
  return k;  // pinned: the daemon's pins (daemon/frame_report.h); frames.jsonl has knobs_pinned instead
}

FrameLogFields frameLogFieldsOf(const FrameRecord& rec) {
  const FrameResult& r = rec.result;
  FrameLogFields f;
  f.trackingAttempted = r.trackingAttempted;
  f.integrated = r.integrated;
  f.icpIterations = r.icpIterations;
  f.residualM = r.residual;
  f.inliers = r.inlierFraction;
  f.trackedVelocityMPerFrame = rec.trackedVelocity;
  if (r.trackingAttempted) {
    f.icpLevelIterations = r.icpLevelIterations;
    f.icpUpdateNorm = r.icpUpdateNorm;
    f.pairAgreement = r.pairAgreement;
    f.modelCoverage = r.modelCoverage;
  }
  if (r.quality.known) f.icpConditioning = r.quality.icpConditioning;
  f.controllerMs = rec.controllerMs;
  f.triggers = triggerNames(rec.decision.triggers);
  f.halfWish = rec.decision.halfPrecision;
  f.knobsPinned = rec.knobsPinned;
  if (rec.decision.level >= 0) f.level = rec.decision.level;
  f.reason = rec.decision.reason;
  if (rec.relocalising) {
    f.relocalisationTries = rec.relocalisation.tries;
    f.relocalisationConfirmed = rec.relocalisation.confirmed;
    f.relocalisationWhy = rec.relocalisation.why;
  }
  if (rec.keyframeAdded) f.keyframeAdded = true;
  f.keyframes = rec.keyframes;
  f.implausible = rec.implausible;
  return f;
}

nlohmann::json frameRecordToJson(const FrameRecord& rec) {
  const FrameResult& r = rec.result;
  nlohmann::json stages = nlohmann::json::object();
  for (int s = 0; s < kStageCount; ++s) stages[stageName(static_cast<Stage>(s))] = r.times.ms[s];
  // The records' fields are written by their tables: the tracking and controller record's (ICP, the
  // controller, the relocaliser, keyframes) first, the knob record's (knobs, controller, computation_ms) and
  // the pose record's (frame, timestamp, pose, state ...) last. Written here: the objects of stage times, half
  // precision, the odometry's verdict, the work counts and the knob sets beside the frame's own.
  nlohmann::json j = {{"ms", stages},
                      {"half", {{"requested", rec.halfRequested}, {"supported", rec.halfSupported},
                                {"applied", rec.halfApplied}}},
                      {"next_knobs", knobsToJson(rec.decision.next)},
                      {"t_start_mono_ns", rec.startMonoNs},
                      {"t_end_mono_ns", rec.endMonoNs}};
  forEachFrameLogValue(frameLogFieldsOf(rec), [&](const FrameLogField& row, nlohmann::json value) {
    (row.logObject ? j[row.logObject] : j)[row.logName] = std::move(value);
  });
  forEachKnobRecordValue(knobFieldsOf(rec), [&](const KnobRecordField& row, nlohmann::json value) {
    if (row.logName) j[row.logName] = std::move(value);  // KNOBS's alone (the pins): not in frames.jsonl
  });
  const FrameOdometry& o = rec.odometry;
  if (o.available || !o.why.empty()) {  // only in runs with odometry: others keep their frames.jsonl
    j["odometry"] = {{"used", o.used}, {"rejected", o.rejected}};  // with the table's available, drift_m, fault
    if (o.fused) j["odometry"]["fused"] = true;
    if (o.calibration) {  // the learnt errors so far (report.html plots them over the run)
      j["odometry"]["scale_error"] = o.calibration->scale;
      j["odometry"]["yaw_scale_error"] = o.calibration->yawScale;
      j["odometry"]["yaw_bias_deg_per_s"] = o.calibration->yawBiasRadPerS * 180.0 / 3.14159265358979323846;
    }
    if (!o.why.empty()) j["odometry"]["why"] = o.why;
  }
  if (r.retracked) j["retracked_from"] = knobsToJson(r.firstKnobs);
  // Issue 43: the work behind integrate's and raycast's times.
  const StageWork& w = r.times.work;
  j["work"] = {{"integrate_blocks", w.integrateBlocks},
               {"carving", w.carvingIntegrations > 0},
               {"raycast_samples_per_pixel", w.raycastPixels ? double(w.raycastSamples) / double(w.raycastPixels) : 0.0},
               {"raycast_lookups_per_pixel", w.raycastPixels ? double(w.raycastLookups) / double(w.raycastPixels) : 0.0}};
  // Device (OpenCL profiling event) times per stage, beside the host times; absent on the cpu backend.
  if (r.times.deviceMs != decltype(r.times.deviceMs){}) {
    nlohmann::json device = nlohmann::json::object();
    for (int s = 0; s < kStageCount; ++s) device[stageName(static_cast<Stage>(s))] = r.times.deviceMs[s];
    j["device_ms"] = device;
  }
  forEachPoseValue(poseFieldsOf(rec), [&](const PoseField& row, nlohmann::json value) {
    if (!row.logName || (row.logWith && !j.contains(row.logWith))) return;  // POSE's alone, or not in this line
    if (!row.logObject)
      j[row.logName] = std::move(value);
    else if (const auto object = j.find(row.logObject); object != j.end())
      (*object)[row.logName] = std::move(value);
  });
  return j;
}

FrameLogSink::FrameLogSink(const std::string& dir, std::shared_ptr<SegmentStore> segments)
    : out_(dir, "frames.jsonl", "per-frame log", "", std::move(segments)) {}

void FrameLogSink::onFrame(const FrameRecord& record) {
  out_.append(frameRecordToJson(record).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) +
              "\n");
}

void FrameLogSink::flush() {}  // every line is written as its frame ends

}  // namespace sb
