#include "daemon/slam_worker.h"

#include <spdlog/spdlog.h>

#include <deque>
#include <optional>

#include "core/error.h"
#include "core/input_file.h"
#include "core/thread_pool.h"
#include "daemon/cpu_affinity.h"
#include "daemon/pass_directories.h"
#include "pipeline/pipeline.h"
#include "runtime/energy_account.h"
#include "runtime/frame_log_sink.h"
#include "runtime/run.h"
#include "runtime/run_setup.h"

namespace sb::daemon {

namespace {

using Clock = std::chrono::steady_clock;
constexpr auto kFlushInterval = std::chrono::seconds(2);  // outputs on disk lag by at most this much
constexpr size_t kFpsWindow = 30;                         // frames in the frame-rate average

}  // namespace

PipelineConfig buildPipelineConfig(const SlamConfig& slam, const SequenceInfo& info) {
  SettingsFile file;
  if (!slam.pipelineConfig.empty()) file = readSettingsFile(slam.pipelineConfig);
  if (!file.controller.is_null())
    throw Error(slam.pipelineConfig + ": 'controller' is not read here; the daemon reads the controller from "
                "slam.controller and slam.controller_config");
  PipelineConfig c = pipelineConfigFor(info, file.pipeline, slam.pipelineConfig);
  finishPipelineConfig(c, slam.pipelineConfig.empty() ? "pipeline config" : slam.pipelineConfig);
  return c;
}

ControllerSettings loadControllerSettings(const SlamConfig& slam, const ControllerContext& context) {
  if (slam.controllerConfig.empty())
    return controllerSettingsFrom(nullptr, slam.controller, true, context, "slam.controller");
  // The shipped config/controller.json wraps the settings in a "controller" key (the form a `slambooster run
  // --config` file takes); the bare settings object is accepted too.
  SettingsFile file = readSettingsFile(slam.controllerConfig);
  const bool wrapped = !file.controller.is_null();
  if (wrapped && !file.pipeline.empty())
    throw Error(slam.controllerConfig + ": holds keys beside 'controller' (" + file.pipeline.begin().key() +
                "); pipeline keys go in slam.pipeline_config");
  return controllerSettingsFrom(wrapped ? file.controller : file.pipeline, slam.controller, false, context,
                                slam.controllerConfig);
}

SlamWorker::SlamWorker(const DaemonConfig& config, const SequenceInfo& sequence, FrameQueue& queue,
                       Publish publish, Finished finished)
    : config_(config),
      sequence_(sequence),
      pipelineConfig_(buildPipelineConfig(config.slam, sequence)),
      queue_(queue),
      publish_(std::move(publish)),
      finished_(std::move(finished)) {
  context_.baseKnobs = pipelineConfig_.knobs;
  settings_ = loadControllerSettings(config.slam, context_);
  stats_.controller = settings_.name;
}

SlamWorker::~SlamWorker() {
  stop_ = true;
  join();
}

void SlamWorker::setPower(power::PowerSampler* sampler, EnergyPublish publish) {
  sampler_ = sampler;
  publishEnergy_ = std::move(publish);
}

void SlamWorker::start() {
  thread_ = std::thread([this] { run(); });
}

void SlamWorker::join() {
  if (thread_.joinable()) thread_.join();
}

void SlamWorker::switchController(const ControllerSettings& settings, const std::string& name) {
  std::lock_guard lock(mutex_);
  settings_ = settings;
  pendingController_ = name;
}

nlohmann::json SlamWorker::changePins(const ControlRequest& request) {
  std::lock_guard lock(mutex_);
  KnobPins pins = pins_;
  for (const auto& knob : request.unpin) pins.unpin(knob);
  for (const auto& [knob, value] : request.pin) pins.pin(knob, value);
  pins_ = pins;
  pinsChanged_ = true;
  return pins_.toJson();
}

ControllerSettings SlamWorker::controllerSettings() const {
  std::lock_guard lock(mutex_);
  return settings_;
}

WorkerStats SlamWorker::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

void SlamWorker::run() {
  try {
    const std::vector<int> cpus = resolveCpus(config_.slam.cpus);
    pinCurrentThread(cpus);  // before the pool: its workers inherit the affinity
    {
      std::lock_guard lock(mutex_);
      stats_.cpus = formatCpuList(cpus);
      stats_.threads = config_.slam.threads ? config_.slam.threads : static_cast<unsigned>(cpus.size());
    }
    spdlog::info("SLAM thread on CPUs {} with {} compute threads", formatCpuList(cpus), stats().threads);
    runPasses();
    std::lock_guard lock(mutex_);
    stats_.state = "finished";
  } catch (const std::exception& e) {
    spdlog::error("SLAM thread stopped: {}", sb::printable(e.what()));
    std::lock_guard lock(mutex_);
    stats_.state = "failed";
    stats_.error = e.what();
  }
  {
    std::lock_guard lock(mutex_);
    stats_.busySince.reset();
  }
  finished_();
}

void SlamWorker::runPasses() {
  ThreadPool pool(stats().threads);
  std::unique_ptr<Run> run;  // of the pass
  const bool loop = config_.source.atEnd == "loop";
  std::optional<PassDirectories> passDirs;  // pass-NNNN under output.dir, within the retention limits
  if (loop) passDirs.emplace(config_.output.dir, passRetention_);
  uint32_t pass = 0;
  std::deque<Clock::time_point> recent;
  double computationSum = 0.0;
  auto lastFlush = Clock::now();
  // The meter's account since the daemon started: the energy of a pass's last frames may land in the next
  // pass's energy.jsonl, and summary.json carries the totals since the start (one pass: exactly this run's).
  std::optional<EnergyAccount> energy;
  if (sampler_) energy.emplace(*sampler_);

  const auto finishPass = [&](bool last, const std::string& error = {}) {
    if (!run) return;
    RunEnd end;
    end.error = error;  // the input failed: summary.json says so ("complete": false, "error")
    end.modelView = config_.output.modelPng ? "last" : "";
    end.mesh = config_.output.mesh;
    end.drainEnergy = last;
    run->finish(end, pool);
    if (config_.output.report) {
      try {
        spdlog::info("report {}", run->writeReport());
      } catch (const std::exception& e) {
        spdlog::warn("report.html not written: {}", sb::printable(e.what()));
      }
    }
    spdlog::info("pass {}: {} frames; outputs in {}", pass, run->runner().frames(), run->dir());
  };
  const auto startPass = [&] {
    const std::string ended = run ? run->dir() : std::string();
    finishPass(false);
    run.reset();  // closes its files
    if (passDirs && !ended.empty()) passDirs->close(ended);
    ++pass;
    const std::string dir = passDirs ? passDirs->next() : config_.output.dir;
    ControllerSettings settings;
    {
      std::lock_guard lock(mutex_);
      settings = settings_;
      if (!pendingController_.empty()) settings.name = pendingController_;
      pendingController_.clear();
      pinsChanged_ = true;
      stats_.pass = pass;
      stats_.outputDir = dir;
      stats_.controller = settings.name;
    }
    auto pipeline = Pipeline::create(pipelineConfig_, sequence_.intrinsics, pool);
    auto controller = createController(settings, context_);
    RunSummary header = runSummaryHeader("daemon", sequence_.path, settings, *controller, *pipeline, pool.threadCount());
    header.daemon = DaemonPass{pass, stats().cpus, stats().threads};
    run = std::make_unique<Run>(
        std::move(pipeline), std::move(controller), sequence_.depthScale,
        RunOutputs{dir, pass == 1 ? sequence_.groundTruthPath : "", header,
                   "slamboosterd " + sequence_.path + " pass " + std::to_string(pass) + " (volume frame)",
                   segments_, config_.output.mesh},
        energy ? &*energy : nullptr);
    if (publishEnergy_)
      run->setEnergyListener([this](const power::FrameEnergy& e) {
        if (e.known) publishEnergy_(e);
      });
  };

  while (!stop_) {
    std::optional<CapturedFrame> item = queue_.pop();
    if (!item || stop_) break;
    if (!run || item->restart) startPass();
    SlamRunner& runner = run->runner();
    std::vector<std::string> pinned;
    {
      std::lock_guard lock(mutex_);
      if (!pendingController_.empty()) {
        runner.setController(createController(pendingController_, settings_, context_));
        stats_.controller = pendingController_;
        pendingController_.clear();
        pinsChanged_ = true;
      }
      if (pinsChanged_) {  // the runner applies the pins over the controller's choice of every frame
        runner.setPins(pins_);
        pinsChanged_ = false;
      }
      pinned = pins_.names();
      stats_.pinned = pins_.toJson();
      stats_.busySince = Clock::now();
    }
    const FrameRecord record = run->step(item->frame);
    publish_(FrameReport{frameRecordToJson(record), std::move(pinned)});
    const auto now = Clock::now();
    recent.push_back(now);
    if (recent.size() > kFpsWindow) recent.pop_front();
    computationSum += record.result.times.computationMs();
    {
      std::lock_guard lock(mutex_);
      stats_.busySince.reset();
      stats_.state = "running";
      ++stats_.frames;
      stats_.tracked += record.result.tracked;
      const bool lost = record.state == TrackingState::lost;
      stats_.lostStretches += lost && stats_.trackingState != "lost";
      stats_.lostFrames += lost;
      stats_.relocalisations += record.state == TrackingState::relocalised;
      stats_.trackingState = trackingStateName(record.state);
      stats_.computationMs = computationSum / static_cast<double>(stats_.frames);
      if (recent.size() > 1)
        stats_.fps = static_cast<double>(recent.size() - 1) /
                     std::chrono::duration<double>(recent.back() - recent.front()).count();
    }
    if (now - lastFlush > kFlushInterval) {
      run->flush();
      lastFlush = now;
    }
  }
  // The energy of the last frames needs the samples after their end: finishPass(true) waits up to the
  // sampler's drain timeout.
  // A failed input (a truncated PNG) fails the pass: its summary and STATUS say so, never "complete".
  const std::string inputError = stop_ ? std::string() : queue_.error();
  if (run) {
    finishPass(true, inputError);  // throws the input's error after writing the summary
  } else if (energy) {
    energy->drain();
  }
  if (!inputError.empty()) throw Error(inputError);
}

}  // namespace sb::daemon
