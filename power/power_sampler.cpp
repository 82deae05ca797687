#include "power/power_sampler.h"

#include <fcntl.h>
#include <poll.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cstring>

#include "core/error.h"

namespace sb::power {

SamplerOptions samplerOptions(const PowerConfig& config, const std::string& tracePath) {
  SamplerOptions o;
  o.maxSampleGapNs = int64_t(config.maxSampleGapMs) * 1'000'000;
  o.drainTimeoutNs = int64_t(config.drainTimeoutMs) * 1'000'000;
  o.tracePath = tracePath;
  return o;
}

int64_t effectiveMaxGapNs(const SamplerOptions& options, const MeterInfo& meter) {
  if (options.maxSampleGapNs > 0) return options.maxSampleGapNs;
  return std::max<int64_t>(3 * meter.nominalPeriodNs, 1'500'000'000);
}

namespace {

LedgerOptions ledgerOptions(const MeterInfo& meter, int64_t maxGapNs) {
  LedgerOptions o;
  o.kind = meter.kind;
  o.maxSampleSpacingNs = maxGapNs;
  return o;
}

}  // namespace

PowerSampler::PowerSampler(std::unique_ptr<Meter> meter, SamplerOptions options, const Clock& clock)
    : meter_(std::move(meter)),
      info_(meter_->info()),
      options_(std::move(options)),
      clock_(clock),
      maxGapNs_(effectiveMaxGapNs(options_, info_)),
      ledger_(ledgerOptions(info_, maxGapNs_)) {
  if (!options_.tracePath.empty())
    trace_ = std::make_unique<PowerTraceWriter>(options_.tracePath, info_, options_.traceSegments);
  int fds[2];
  if (pipe2(fds, O_CLOEXEC | O_NONBLOCK) != 0) throw Error(std::string("power sampler: pipe2: ") + std::strerror(errno));
  wakeRead_.reset(fds[0]);
  wakeWrite_.reset(fds[1]);
  status_ = meter_->status();
  wasConnected_ = true;  // a meter that starts disconnected ("none") is reported lost at the first poll
}

PowerSampler::~PowerSampler() { stop(); }

void PowerSampler::setIdleWatts(double watts) {
  std::lock_guard<std::mutex> lock(mutex_);
  ledger_.setIdleWatts(watts);
}

void PowerSampler::setCallback(Callback callback) { callback_ = std::move(callback); }

double PowerSampler::measureIdle(double seconds) {
  if (thread_.joinable()) throw Error("power sampler: measureIdle() must come before start()");
  LedgerOptions o = ledgerOptions(info_, maxGapNs_);
  o.retainNs = INT64_MAX;
  EnergyLedger idle(o);
  const int64_t deadline = clock_.nowNs() + secondsToNs(seconds);
  std::vector<PowerSample> batch;
  int64_t first = 0, last = 0;
  while (clock_.nowNs() < deadline) {
    batch.clear();
    meter_->poll(batch);
    for (const PowerSample& s : batch) {
      if (!idle.addSample(s)) continue;
      if (first == 0) first = s.tNs;
      last = s.tNs;
      if (trace_) trace_->sample(s);
    }
    if (trace_) trace_->flush();
    if (clock_.nowNs() < deadline) waitForMeter();
  }
  const Coverage c = idle.energyBetween(first, last);
  if (c.knownNs <= 0)
    throw Error("idle baseline: the " + info_.name + " meter ('" + info_.device + "') gave fewer than two samples in " +
                std::to_string(seconds) + " s (is it connected and its output on? raise idle_baseline_s?)");
  const double watts = c.joules / nsToSeconds(c.knownNs);
  spdlog::info("idle baseline: {:.3f} W over {:.1f} s ({} meter)", watts, nsToSeconds(c.knownNs), info_.name);
  setIdleWatts(watts);
  return watts;
}

void PowerSampler::start() {
  if (thread_.joinable() || stopped_) throw Error("power sampler: start() called twice");
  startNs_ = clock_.nowNs();
  thread_ = std::thread([this] { run(); });
}

void PowerSampler::addFrame(const FrameInterval& frame) {
  bool wake;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ledger_.addFrame(frame);
    wake = ledger_.hasReady();  // resolved at once (samples past its end already in, or no meter)
  }
  if (wake) wakeThread();  // results are delivered on the sampler thread
}

void PowerSampler::wakeThread() {
  const char byte = 1;
  [[maybe_unused]] const ssize_t n = ::write(wakeWrite_.get(), &byte, 1);
}

std::vector<FrameEnergy> PowerSampler::takeResults() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<FrameEnergy> out;
  out.swap(results_);
  return out;
}

EnergyTotals PowerSampler::totals() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return ledger_.totals();
}

MeterStatus PowerSampler::meterStatus() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return status_;
}

void PowerSampler::deliver(std::vector<FrameEnergy> results) {
  if (results.empty()) return;
  if (callback_) {
    for (const FrameEnergy& e : results) callback_(e);
    return;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  results_.insert(results_.end(), results.begin(), results.end());
}

void PowerSampler::pollOnce() {
  std::vector<PowerSample> batch;
  MeterStatus status;
  try {
    meter_->poll(batch);
    status = meter_->status();
  } catch (const std::exception& e) {  // a sysfs read or library call failed: a gap, not a crash
    status = meter_->status();
    status.connected = false;
    status.message = e.what();
  }
  const int64_t now = clock_.nowNs();
  std::vector<FrameEnergy> ready;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const PowerSample& s : batch) {
      if (ledger_.addSample(s) && trace_) trace_->sample(s);
    }
    std::string lostReason;
    if (!status.connected && (wasConnected_ || !batch.empty())) {
      lostReason = status.message.empty() ? "meter disconnected" : status.message;
      if (wasConnected_ && everConnected_)
        spdlog::warn("power meter {}: {}; energy unknown until it is back", info_.name, lostReason);
      else if (wasConnected_)
        spdlog::info("power meter {}: {}; per-frame energy is unknown", info_.name, lostReason);
    } else if (status.connected && !ledger_.lost()) {
      const int64_t since = ledger_.hasSamples() ? ledger_.lastSampleNs() : startNs_;
      if (now - since > maxGapNs_) {
        lostReason = "no power samples for more than " + std::to_string(maxGapNs_ / 1'000'000) + " ms";
        spdlog::warn("power meter {} ('{}'): {}", info_.name, info_.device, lostReason);
      }
    }
    if (!lostReason.empty()) {
      ledger_.meterLost(lostReason);
      if (trace_) trace_->lost(now);
    }
    if (trace_) trace_->flush();
    wasConnected_ = status.connected;
    everConnected_ = everConnected_ || status.connected;
    status_ = status;
    ready = ledger_.takeReady();
  }
  deliver(std::move(ready));
}

void PowerSampler::waitForMeter() {
  const int64_t periodNs = std::clamp<int64_t>(meter_->pollPeriodNs(), 0, 100'000'000);
  pollfd fds[2] = {{wakeRead_.get(), POLLIN, 0}, {meter_->waitFd(), POLLIN, 0}};
  const nfds_t count = fds[1].fd >= 0 ? 2 : 1;
  ::poll(fds, count, static_cast<int>((periodNs + 999'999) / 1'000'000));
  char drain[64];
  while (::read(wakeRead_.get(), drain, sizeof drain) > 0) {
  }
}

void PowerSampler::run() {
  for (;;) {
    pollOnce();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stopping_) break;
    }
    waitForMeter();
  }
  // Drain: keep polling until every frame has a sample after its end, or the timeout (on the meter's clock,
  // and in real time too, so that a clock that stands still cannot hold the shutdown).
  const int64_t deadline = clock_.nowNs() + options_.drainTimeoutNs;
  const auto realDeadline = std::chrono::steady_clock::now() + std::chrono::nanoseconds(options_.drainTimeoutNs);
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (ledger_.pendingFrames() == 0 || ledger_.lost()) break;
    }
    if (clock_.nowNs() >= deadline || std::chrono::steady_clock::now() >= realDeadline) break;
    waitForMeter();
    pollOnce();
  }
  std::vector<FrameEnergy> rest;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    rest = ledger_.finish("no power sample after the frame's end before the sampler stopped");
    if (trace_) trace_->flush();
  }
  deliver(std::move(rest));
}

std::vector<FrameEnergy> PowerSampler::stop() {
  if (thread_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    wakeThread();
    thread_.join();
  } else if (!stopped_) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<FrameEnergy> rest = ledger_.finish("the power sampler was never started");
    results_.insert(results_.end(), rest.begin(), rest.end());
  }
  stopped_ = true;
  return takeResults();
}

}  // namespace sb::power
