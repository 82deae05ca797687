#pragma once
// The raw power trace of a profiling run, written beside the per-frame log so that the run can be
// re-accounted later (`slambooster energy --trace T --frames F`) or replayed (meter "file").
//
// Format (CSV, one event per line, times CLOCK_MONOTONIC ns of the recording machine):
//   # {"format":"slambooster-power-trace","version":1,"meter":"smartpower2","device":"/dev/ttyUSB0",
//   #  "kind":"instantaneous","nominal_period_ns":1000000000,"clock":"CLOCK_MONOTONIC"}   (one line)
//   t_ns,watts,volts,amps,event
//   12345678901,4.321,5.102,0.847,
//   12346678901,4.298,,,gap        <- a sample after a meter gap (volts/amps empty when unknown)
//   12347000000,,,,lost            <- the meter stopped delivering data at this time
// Numbers are written in their shortest exact form, so re-accounting reproduces the live numbers.

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "core/rotating_file.h"
#include "power/meter.h"

namespace sb::power {

struct TraceEvent {
  PowerSample sample;  // for a lost event only sample.tNs is set
  bool lost = false;
};

struct PowerTrace {
  MeterInfo meter;                // name, device, kind, nominal period of the recording
  std::vector<TraceEvent> events;
};

class PowerTraceWriter {
 public:
  // Creates (truncates) `path` and writes the header. With `segments` the trace is rotated instead
  // (power-000001.csv, ..., each with the header; core/rotating_file.h). Throws sb::Error naming the file.
  PowerTraceWriter(const std::string& path, const MeterInfo& meter,
                   std::shared_ptr<SegmentStore> segments = nullptr);
  ~PowerTraceWriter();
  PowerTraceWriter(const PowerTraceWriter&) = delete;
  PowerTraceWriter& operator=(const PowerTraceWriter&) = delete;

  void sample(const PowerSample& s);
  void lost(int64_t tNs);
  // The sampler flushes after every batch: a crash loses at most one poll's samples. A failed write is logged
  // (once until writes succeed again), never thrown: the meter's accounting goes on without its trace.
  void flush();

  const std::string& path() const { return file_.path(); }  // the file being written now

 private:
  RotatingFile file_;
  std::string pending_;  // lines since the last flush
  bool failing_ = false;
};

// Reads a trace. Throws sb::Error naming the file and line for anything malformed.
PowerTrace readPowerTrace(const std::string& path);

}  // namespace sb::power
