#include "runtime/frame_log_sink.h"

#include <Eigen/Geometry>

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

nlohmann::json frameRecordToJson(const FrameRecord& rec) {
  const FrameResult& r = rec.result;
  nlohmann::json stages = nlohmann::json::object();
  for (int s = 0; s < kStageCount; ++s) stages[stageName(static_cast<Stage>(s))] = r.times.ms[s];
  // The knob record's fields (knobs, controller, computation_ms) and the pose record's (frame, timestamp, pose,
  // state ...) are written by their tables, below.
  nlohmann::json j = {{"ms", stages},
                      {"tracking_attempted", r.trackingAttempted},
                      {"integrated", r.integrated},
                      {"icp_iterations", r.icpIterations},
                      {"residual_m", r.residual},
                      {"inliers", r.inlierFraction},
                      {"tracked_velocity_m_per_frame", rec.trackedVelocity},
                      {"controller_ms", rec.controllerMs},
                      {"triggers", triggerNames(rec.decision.triggers)},
                      {"half_wish", rec.decision.halfPrecision},
                      {"half", {{"requested", rec.halfRequested}, {"supported", rec.halfSupported},
                                {"applied", rec.halfApplied}}},
                      {"next_knobs", knobsToJson(rec.decision.next)},
                      {"knobs_pinned", rec.knobsPinned},
                      {"t_start_mono_ns", rec.startMonoNs},
                      {"t_end_mono_ns", rec.endMonoNs}};
  forEachKnobRecordValue(knobFieldsOf(rec), [&](const KnobRecordField& row, nlohmann::json value) {
    if (row.logName) j[row.logName] = std::move(value);  // KNOBS's alone (the pins): not in frames.jsonl
  });
  if (rec.decision.level >= 0) j["level"] = rec.decision.level;
  if (r.trackingAttempted) {
    j["icp_level_iterations"] = {r.icpLevelIterations[0], r.icpLevelIterations[1], r.icpLevelIterations[2]};
    j["icp_update_norm"] = r.icpUpdateNorm;
  }
  if (r.quality.known) j["icp_conditioning"] = r.quality.icpConditioning;
  if (r.trackingAttempted) j["pair_agreement"] = r.pairAgreement;
  if (rec.relocalising)
    j["relocalisation"] = {{"tries", rec.relocalisation.tries},
                           {"confirmed", rec.relocalisation.confirmed},
                           {"why", rec.relocalisation.why}};
  if (rec.keyframeAdded) j["keyframe_added"] = true;
  j["keyframes"] = rec.keyframes;
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
  if (!rec.implausible.empty()) j["implausible"] = rec.implausible;
  if (r.retracked) j["retracked_from"] = knobsToJson(r.firstKnobs);
  // Issue 43: the work behind integrate's and raycast's times.
  const StageWork& w = r.times.work;
  j["work"] = {{"integrate_blocks", w.integrateBlocks},
               {"carving", w.carvingIntegrations > 0},
               {"raycast_samples_per_pixel", w.raycastPixels ? double(w.raycastSamples) / double(w.raycastPixels) : 0.0},
               {"raycast_lookups_per_pixel", w.raycastPixels ? double(w.raycastLookups) / double(w.raycastPixels) : 0.0}};
  if (!rec.decision.reason.empty()) j["reason"] = rec.decision.reason;
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
