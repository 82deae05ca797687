#include "runtime/summary_sink.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <thread>

#include "core/error.h"
#include "runtime/frame_log_sink.h"
#include "runtime/line_file.h"

namespace sb {

void RunStats::add(const FrameRecord& rec) {
  const FrameResult& r = rec.result;
  ++frames;
  trackingAttempted += r.trackingAttempted;
  tracked += r.tracked;
  integrated += r.integrated;
  corrected += r.poseOverridden;
  halfWishes += rec.decision.halfPrecision;
  unconstrained += r.quality.known && !r.quality.constrained;
  retracked += r.retracked;
  halfApplied += rec.halfApplied;
  for (int s = 0; s < kStageCount; ++s) stageSums.ms[s] += r.times.ms[s];
  controllerMsSum += rec.controllerMs;
  for (const std::string& t : triggerNames(rec.decision.triggers)) ++triggerCounts[t];
  ++knobCounts[formatKnobs(r.knobs)];
  ++controllerCounts[rec.controller];
  ++stateFrames[static_cast<size_t>(rec.state)];
  if (rec.state == TrackingState::lost) {
    if (currentLost++ == 0) ++lostStretches;
    longestLost = std::max(longestLost, currentLost);
  } else {
    if (rec.state == TrackingState::relocalised && currentLost > 0) {
      ++recoveries;
      recoveryFramesSum += currentLost;
      longestRecovery = std::max(longestRecovery, currentLost);
    }
    currentLost = 0;
  }
}

nlohmann::json RunStats::toJson() const {
  nlohmann::json j;
  j["frames"] = frames;
  j["tracking_attempted"] = trackingAttempted;
  j["tracked"] = tracked;
  j["tracked_percent"] = trackedPercent();
  j["integrated"] = integrated;
  j["corrected"] = corrected;
  j["half_wish_frames"] = halfWishes;
  j["unconstrained"] = unconstrained;
  j["retracked"] = retracked;
  j["half_applied_frames"] = halfApplied;
  j["computation_ms_per_frame"] = computationMsPerFrame();
  j["controller_ms_per_frame"] = frames ? controllerMsSum / frames : 0.0;
  nlohmann::json stages = nlohmann::json::object();
  for (int s = 0; s < kStageCount; ++s)
    stages[stageName(static_cast<Stage>(s))] = frames ? stageSums.ms[s] / frames : 0.0;
  j["stage_ms_per_frame"] = stages;
  j["triggers"] = triggerCounts;
  j["knob_frames"] = knobCounts;
  j["controller_frames"] = controllerCounts;
  nlohmann::json states = nlohmann::json::object();
  for (int s = 0; s < kTrackingStateCount; ++s) states[trackingStateName(static_cast<TrackingState>(s))] = stateFrames[s];
  j["tracking_state"] = {{"frames", states},
                         {"lost_stretches", lostStretches},
                         {"longest_lost_frames", longestLost},
                         {"recoveries", recoveries},
                         {"mean_frames_to_recover", recoveries ? double(recoveryFramesSum) / recoveries : 0.0},
                         {"longest_frames_to_recover", longestRecovery},
                         {"lost_at_end", currentLost > 0}};
  return j;
}

std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string fallback;
  for (std::string line; std::getline(in, line);) {
    const size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::string key = line.substr(0, colon), value = line.substr(colon + 1);
    while (!key.empty() && (key.back() == ' ' || key.back() == '\t')) key.pop_back();
    while (!value.empty() && value.front() == ' ') value.erase(0, 1);
    if (key == "model name" && !value.empty()) return value;
    if ((key == "Hardware" || key == "Processor") && fallback.empty()) fallback = value;
  }
  return fallback.empty() ? "unknown" : fallback;
}

nlohmann::json machineJson(unsigned threadsUsed, const std::string& backend, const std::string& device) {
  char host[256] = {};
  gethostname(host, sizeof(host) - 1);
  return {{"host", std::string(host)},
          {"cpu_model", cpuModel()},
          {"cores_online", std::thread::hardware_concurrency()},
          {"threads_used", threadsUsed},
          {"backend", backend},
          {"device", device}};
}

SummarySink::SummarySink(const std::string& path, const std::string& groundTruthPath, nlohmann::json extra,
                         std::shared_ptr<SegmentStore> segments)
    : path_(path),
      groundTruthPath_(groundTruthPath),
      segments_(std::move(segments)),
      extra_(std::move(extra)) {
  if (!extra_.is_object()) extra_ = nlohmann::json::object();
}

void SummarySink::onFrame(const FrameRecord& record) {
  stats_.add(record);
  // A snapshot per frame (without the ATE, computed at flush()): after a crash summary.json agrees with the
  // trajectory and the per-frame log within one frame.
  nlohmann::json snapshot = extra_;
  snapshot.update(stats_.toJson());
  write(snapshot);
}

void SummarySink::flush() {
  summary_ = extra_;
  summary_.update(stats_.toJson());
  ate_.reset();
  if (!groundTruthPath_.empty() && readTrajectory_ && stats_.frames > 0) {
    try {
      if (!groundTruth_) groundTruth_ = readTumTrajectory(groundTruthPath_);
      ate_ = computeAte(readTrajectory_(), *groundTruth_);
      summary_["ate"] = {{"rmse_m", ate_->rmse},       {"mean_m", ate_->mean},
                         {"max_m", ate_->max},         {"median_m", ate_->median},
                         {"matches", ate_->matches},   {"unaligned_mean_m", ate_->unalignedMean}};
    } catch (const Error& e) {
      summary_["ate_error"] = e.what();
    }
  }
  write(summary_);
}

void SummarySink::write(const nlohmann::json& summary) const {
  // Whole or not at all: a temporary file renamed over the old one (which stays as it was on failure).
  const std::string tmp = path_ + ".tmp";
  const std::string text = summary.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  const auto writeTemporary = [&] {
    try {
      LineFile(tmp, "summary").append(text);
    } catch (...) {
      std::remove(tmp.c_str());
      throw;
    }
  };
  try {
    if (segments_)
      segments_->writeMakingRoom(writeTemporary);  // a full disk: the oldest segments go, as for the others
    else
      writeTemporary();
  } catch (const Error& e) {
    throw Error(std::string(e.what()) + "; '" + path_ + "' keeps the previous summary");
  }
  if (std::rename(tmp.c_str(), path_.c_str()) != 0) throw Error("cannot rename '" + tmp + "' to '" + path_ + "'");
}

}  // namespace sb
