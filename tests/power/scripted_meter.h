#pragma once
// A meter driven by the test: samples and connection changes are queued from the test thread and handed
// out by poll() on the sampler thread. Optionally advances a ManualClock on every poll (idle measurement).

#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "power/clock.h"
#include "power/meter.h"

namespace sb::test {

class ScriptedMeter final : public power::Meter {
 public:
  explicit ScriptedMeter(power::SampleKind kind = power::SampleKind::instantaneous, int64_t periodNs = 10'000'000) {
    info_.name = "scripted";
    info_.device = "test";
    info_.kind = kind;
    info_.nominalPeriodNs = periodNs;
  }

  void push(int64_t tNs, double watts, bool gapBefore = false) {
    std::lock_guard<std::mutex> lock(mutex_);
    power::PowerSample s;
    s.tNs = tNs;
    s.watts = watts;
    s.gapBefore = gapBefore;
    queue_.push_back(s);
  }
  void setConnected(bool connected, const std::string& message = "") {
    std::lock_guard<std::mutex> lock(mutex_);
    status_.connected = connected;
    status_.message = message;
  }
  // Every poll advances `clock` by `stepNs` and returns one sample of `watts` at the new time.
  void autoSample(power::ManualClock* clock, int64_t stepNs, double watts) {
    std::lock_guard<std::mutex> lock(mutex_);
    clock_ = clock;
    stepNs_ = stepNs;
    autoWatts_ = watts;
  }
  // poll() throws this (a plain std::runtime_error, as a library might) while set; empty = no throwing.
  void throwOnPoll(const std::string& what) {
    std::lock_guard<std::mutex> lock(mutex_);
    throw_ = what;
  }
  size_t polls() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return polls_;
  }

  const power::MeterInfo& info() const override { return info_; }
  void poll(std::vector<power::PowerSample>& out) override {
    std::lock_guard<std::mutex> lock(mutex_);
    ++polls_;
    if (!throw_.empty()) throw std::runtime_error(throw_);
    if (clock_) {
      clock_->advance(stepNs_);
      power::PowerSample s;
      s.tNs = clock_->nowNs();
      s.watts = autoWatts_;
      queue_.push_back(s);
    }
    out.insert(out.end(), queue_.begin(), queue_.end());
    status_.samples += queue_.size();
    queue_.clear();
  }
  power::MeterStatus status() const override {
    std::lock_guard<std::mutex> lock(mutex_);
    return status_;
  }
  int64_t pollPeriodNs() const override { return 1'000'000; }

 private:
  mutable std::mutex mutex_;
  power::MeterInfo info_;
  power::MeterStatus status_;
  std::vector<power::PowerSample> queue_;
  power::ManualClock* clock_ = nullptr;
  int64_t stepNs_ = 0;
  double autoWatts_ = 0.0;
  size_t polls_ = 0;
  std::string throw_;
};

}  // namespace sb::test
