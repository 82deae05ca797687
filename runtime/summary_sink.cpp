#include "runtime/summary_sink.h"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <thread>

#include "core/disk_full.h"
#include "core/error.h"
#include "core/exclusive_file.h"
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
  stageSums.work.integrateBlocks += r.times.work.integrateBlocks;
  stageSums.work.carvingIntegrations += r.times.work.carvingIntegrations;
  stageSums.work.raycastPixels += r.times.work.raycastPixels;
  stageSums.work.raycastSamples += r.times.work.raycastSamples;
  stageSums.work.raycastLookups += r.times.work.raycastLookups;
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

void RunStats::fill(RunSummary& s) const {
  s.frames = frames;
  s.trackingAttempted = trackingAttempted;
  s.tracked = tracked;
  s.trackedPercent = trackedPercent();
  s.integrated = integrated;
  s.corrected = corrected;
  s.halfWishFrames = halfWishes;
  s.unconstrained = unconstrained;
  s.retracked = retracked;
  s.halfAppliedFrames = halfApplied;
  s.computationMsPerFrame = computationMsPerFrame();
  s.controllerMsPerFrame = frames ? controllerMsSum / frames : 0.0;
  s.stageMsPerFrame.clear();
  for (int st = 0; st < kStageCount; ++st)
    s.stageMsPerFrame[stageName(static_cast<Stage>(st))] = frames ? stageSums.ms[st] / frames : 0.0;
  // Issue 43: the work of integrate (per integration) and of the frames' last raycasts (per pixel).
  const StageWork& w = stageSums.work;
  s.work = {{"integrate_blocks_per_integration", integrated ? double(w.integrateBlocks) / integrated : 0.0},
            {"carving_integrations", double(w.carvingIntegrations)},
            {"raycast_samples_per_pixel", w.raycastPixels ? double(w.raycastSamples) / double(w.raycastPixels) : 0.0},
            {"raycast_lookups_per_pixel", w.raycastPixels ? double(w.raycastLookups) / double(w.raycastPixels) : 0.0}};
  s.triggers = triggerCounts;
  s.knobFrames = knobCounts;
  s.controllerFrames = controllerCounts;
  TrackingStateSummary& t = s.trackingState;
  t.frames.clear();
  for (int st = 0; st < kTrackingStateCount; ++st)
    t.frames[trackingStateName(static_cast<TrackingState>(st))] = stateFrames[st];
  t.lostStretches = lostStretches;
  t.longestLostFrames = longestLost;
  t.recoveries = recoveries;
  t.meanFramesToRecover = recoveries ? double(recoveryFramesSum) / recoveries : 0.0;
  t.longestFramesToRecover = longestRecovery;
  t.lostAtEnd = currentLost > 0;
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

MachineInfo thisMachine(unsigned threadsUsed, const std::string& backend, const std::string& device) {
  char host[256] = {};
  gethostname(host, sizeof(host) - 1);
  return MachineInfo{std::string(host), cpuModel(), std::thread::hardware_concurrency(), threadsUsed, backend,
                     device};
}

SummarySink::SummarySink(const std::string& path, const std::string& groundTruthPath, RunSummary header,
                         std::shared_ptr<SegmentStore> segments)
    : path_(path),
      groundTruthPath_(groundTruthPath),
      segments_(std::move(segments)),
      header_(std::move(header)) {
  // The room for the last summary, taken now: a disk that cannot hold it is said at the start (with rotation,
  // the oldest segments give way first, as for every write).
  const auto keepRoom = [&] { reserve_ = std::make_unique<ReservedFile>(path_, kSummaryReserveBytes); };
  if (segments_)
    segments_->writeMakingRoom(keepRoom);
  else
    keepRoom();
}

void SummarySink::onFrame(const FrameRecord& record) {
  stats_.add(record);
  // A snapshot per frame (without the ATE, computed at flush()): after a crash summary.json agrees with the
  // trajectory and the per-frame log within one frame.
  RunSummary snapshot = header_;
  stats_.fill(snapshot);
  write(snapshot);
}

void SummarySink::flush() {
  summary_ = header_;
  stats_.fill(summary_);
  ate_.reset();
  if (!groundTruthPath_.empty() && readTrajectory_ && stats_.frames > 0) {
    try {
      if (!groundTruth_) groundTruth_ = readTumTrajectory(groundTruthPath_);
      ate_ = computeAte(readTrajectory_(), *groundTruth_);
      summary_.ate = AteSummary{ate_->rmse, ate_->mean, ate_->max, ate_->median, ate_->unalignedMean, ate_->matches};
    } catch (const Error& e) {
      summary_.ateError = e.what();
    }
  }
  write(summary_);
}

void SummarySink::write(const RunSummary& summary) {
  // Whole or not at all: a new temporary file (core/exclusive_file.h) renamed over the old one (which stays
  // as it was on failure).
  const std::string text =
      summary.toJson().dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  const auto writeTemporary = [&] {
    TemporaryFile tmp(path_);  // removed unless committed
    LineFile(UniqueFd(::fcntl(tmp.fd(), F_DUPFD_CLOEXEC, 0)), tmp.path(), "summary").append(text);
    tmp.commit();
  };
  try {
    if (segments_)
      segments_->writeMakingRoom(writeTemporary);  // a full disk: the oldest segments go, as for the others
    else
      writeTemporary();
  } catch (const Error& e) {
    const std::string message = std::string(e.what()) + "; '" + path_ + "' keeps the previous summary";
    if (!summary.complete || !reserve_) {
      if (dynamic_cast<const DiskFullError*>(&e)) throw DiskFullError(message, path_);
      throw WriteError(message, path_);
    }
    // The last summary: into the room kept aside (whatever the failure: it needs no new block).
    try {
      reserve_->replaceTarget(text);
    } catch (const Error& reserved) {
      throw WriteError(message + "; and from the room kept aside: " + reserved.what(), path_);
    }
    reserve_.reset();
    spdlog::warn("summary.json: the last summary was written into the room kept aside for it ({})", e.what());
    return;
  }
  // Twice the largest summary so far kept aside (best effort: on a full disk the room kept stays as it was).
  if (reserve_ && 2 * uint64_t(text.size()) > reserve_->bytes()) reserve_->grow(2 * uint64_t(text.size()));
}

}  // namespace sb
