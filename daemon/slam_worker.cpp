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
#include "daemon/frame_report.h"
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

odometry::OdometryConfig buildOdometryConfig(const SlamConfig& slam) {
  if (slam.pipelineConfig.empty()) return {};
  return odometry::odometryConfigFrom(readSettingsFile(slam.pipelineConfig).odometry, slam.pipelineConfig);
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
      odometryConfig_(buildOdometryConfig(config.slam)),
      queue_(queue),
      publish_(std::move(publish)),
      finished_(std::move(finished)) {
  context_.baseKnobs = pipelineConfig_.knobs;
  settings_ = loadControllerSettings(config.slam, context_);
  stats_.controller = settings_.name;
  if (!config.output.navmap.empty())
    maps_ = std::make_unique<MapPublisher>(config.output, pipelineConfig_, sequence, config.source.odometry != "none");
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
  settings_.name = name;
  controllerChanged_ = true;
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

struct SlamWorker::Passes {
  ThreadPool pool;
  std::unique_ptr<Run> run;                 // of the pass in hand
  std::optional<PassDirectories> dirs;      // looping: pass-NNNN under output.dir, within the retention limits
  uint32_t pass = 0;
  // The meter's account since the daemon started: the energy of a pass's last frames may land in the next
  // pass's energy.jsonl, and summary.json carries the totals since the start (one pass: exactly this run's).
  std::optional<EnergyAccount> energy;
  std::deque<Clock::time_point> recent;     // the last frames' ends, for the frame rate
  double computationSum = 0.0;
  Clock::time_point lastFlush = Clock::now();
  explicit Passes(unsigned threads) : pool(threads) {}
};

void SlamWorker::runPasses() {
  Passes p(stats().threads);
  if (config_.source.atEnd == "loop") p.dirs.emplace(config_.output.dir, passRetention_);
  if (sampler_) p.energy.emplace(*sampler_);
  while (!stop_) {
    std::optional<CapturedFrame> item = queue_.pop();
    if (!item || stop_) break;
    if (!p.run || item->restart) startPass(p);
    std::vector<std::string> pinned = applyChanges(p.run->runner());
    const FrameRecord record = p.run->step(item->frame);
    if (maps_) maps_->afterFrame(*p.run, p.run->runner().frames());
    publish_(frameReport(record, std::move(pinned)));
    countFrame(p, record);
  }
  // A failed input (a truncated PNG) fails the pass: its summary and STATUS say so, never "complete".
  const std::string inputError = stop_ ? std::string() : queue_.error();
  if (p.run) {
    finishPass(p, true, inputError);  // throws the input's error after writing the summary
  } else if (p.energy) {
    p.energy->drain();
  }
  if (!inputError.empty()) throw Error(inputError);
}

void SlamWorker::finishPass(Passes& p, bool last, const std::string& error) {
  RunEnd end;
  end.error = error;  // the input failed: summary.json says so ("complete": false, "error")
  end.modelView = config_.output.modelPng ? "last" : "";
  end.mesh = config_.output.mesh;
  end.drainEnergy = last;  // the energy of the last frames needs the samples after their end
  p.run->finish(end, p.pool);
  if (config_.output.report) {
    try {
      spdlog::info("report {}", p.run->writeReport());
    } catch (const std::exception& e) {
      spdlog::warn("report.html not written: {}", sb::printable(e.what()));
    }
  }
  spdlog::info("pass {}: {} frames; outputs in {}", p.pass, p.run->runner().frames(), p.run->dir());
}

void SlamWorker::startPass(Passes& p) {
  if (p.run) {
    const std::string ended = p.run->dir();
    finishPass(p, false);
    p.run.reset();  // closes its files
    if (p.dirs) p.dirs->close(ended);
  }
  ++p.pass;
  const std::string dir = p.dirs ? p.dirs->next() : config_.output.dir;
  ControllerSettings settings;
  {
    std::lock_guard lock(mutex_);
    settings = settings_;  // the controller in force, switched or not: the new run starts with it
    controllerChanged_ = false;
    pinsChanged_ = true;
    stats_.pass = p.pass;
    stats_.outputDir = dir;
    stats_.controller = settings.name;
  }
  auto pipeline = Pipeline::create(pipelineConfig_, sequence_.intrinsics, p.pool);
  auto controller = createController(settings, context_);
  RunSummary header =
      runSummaryHeader("daemon", sequence_.path, settings, *controller, *pipeline, odometryConfig_,
                       p.pool.threadCount());
  header.daemon = DaemonPass{p.pass, stats().cpus, stats().threads};
  header.odometry = odometry_.summary();
  RunOutputs outputs;
  outputs.dir = dir;
  outputs.groundTruthPath = p.pass == 1 ? sequence_.groundTruthPath : "";
  outputs.summary = header;
  outputs.comment = "slamboosterd " + sequence_.path + " pass " + std::to_string(p.pass) + " (volume frame)";
  outputs.segments = segments_;
  outputs.mapSlabs = config_.output.mesh;
  outputs.mapStore = config_.output.mapStore;
  outputs.mapStoreOptions.keepSlabBytes = static_cast<uint64_t>(config_.output.mapStoreKeepMib * 1024.0 * 1024.0);
  outputs.keepSlabBytes = static_cast<uint64_t>(config_.output.rotation.keepSlabsMib * 1024.0 * 1024.0);
  outputs.slabRetention = segments_ ? segments_ : passRetention_;
  outputs.mapSink = maps_ ? maps_->startPass(p.pass) : nullptr;
  p.run = std::make_unique<Run>(std::move(pipeline), std::move(controller), sequence_.depthScale, odometryConfig_,
                                outputs,
                                p.energy ? &*p.energy : nullptr);
  if (odometry_.track) p.run->runner().setOdometry(odometry_.track);
  if (publishEnergy_)
    p.run->setEnergyListener([this](const power::FrameEnergy& e) {
      if (e.known) publishEnergy_(e);
    });
}

std::vector<std::string> SlamWorker::applyChanges(SlamRunner& runner) {
  std::lock_guard lock(mutex_);
  if (controllerChanged_) {
    runner.setController(createController(settings_, context_));
    stats_.controller = settings_.name;
    controllerChanged_ = false;
    pinsChanged_ = true;
  }
  if (pinsChanged_) {  // the runner applies the pins over the controller's choice of every frame
    runner.setPins(pins_);
    pinsChanged_ = false;
  }
  stats_.pinned = pins_.toJson();
  stats_.busySince = Clock::now();
  return pins_.names();
}

void SlamWorker::countFrame(Passes& p, const FrameRecord& record) {
  const auto now = Clock::now();
  p.recent.push_back(now);
  if (p.recent.size() > kFpsWindow) p.recent.pop_front();
  p.computationSum += record.result.times.computationMs();
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
    stats_.keptMap = record.keptMap == KeptMap::none ? std::string() : keptMapName(record.keptMap);
    const FrameOdometry& o = record.odometry;
    stats_.odometryFrames += o.available;
    stats_.odometryMissing += !o.available && !o.why.empty();
    stats_.odometryRejected += o.rejected;
    stats_.odometryOnlyFrames += record.state == TrackingState::odometry;
    stats_.odometryWhy = o.available && !o.rejected ? std::string() : o.why;
    stats_.computationMs = p.computationSum / static_cast<double>(stats_.frames);
    if (p.recent.size() > 1)
      stats_.fps = static_cast<double>(p.recent.size() - 1) /
                   std::chrono::duration<double>(p.recent.back() - p.recent.front()).count();
  }
  if (now - p.lastFlush > kFlushInterval) {
    p.run->flush();
    p.lastFlush = now;
  }
}

}  // namespace sb::daemon
