#include "power/offline_accounting.h"

#include <climits>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/input_file.h"
#include "power/power_sampler.h"

namespace sb::power {

std::vector<FrameInterval> readFrameIntervals(const std::string& path) {
  InputFile in(path, "frame log");
  std::vector<FrameInterval> frames;
  std::string line;
  size_t lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    if (line.empty()) continue;
    const std::string where = "frame log '" + path + "' line " + std::to_string(lineNo);
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(line);
    } catch (const nlohmann::json::exception& e) {
      throw Error(where + ": not valid JSON: " + e.what());
    }
    for (const char* key : {kFrameIndexKey, kFrameStartKey, kFrameEndKey}) {
      if (!j.is_object() || !j.contains(key) || !j[key].is_number_integer())
        throw Error(where + ": needs integer '" + key + "' (per-frame CLOCK_MONOTONIC start/end in ns; " +
                    "logs written before the run loop recorded them cannot be re-accounted)");
    }
    FrameInterval f;
    f.frame = j[kFrameIndexKey].get<uint64_t>();
    f.startNs = j[kFrameStartKey].get<int64_t>();
    f.endNs = j[kFrameEndKey].get<int64_t>();
    if (f.endNs < f.startNs) throw Error(where + ": '" + kFrameEndKey + "' is before '" + kFrameStartKey + "'");
    frames.push_back(f);
  }
  return frames;
}

OfflineResult accountOffline(const PowerTrace& trace, const std::vector<FrameInterval>& frames,
                             const OfflineOptions& options) {
  SamplerOptions sampler;
  sampler.maxSampleGapNs = options.maxSampleGapNs;
  LedgerOptions o;
  o.kind = trace.meter.kind;
  o.maxSampleSpacingNs = effectiveMaxGapNs(sampler, trace.meter);
  o.idleWatts = options.idleWatts;
  o.retainNs = INT64_MAX;  // the whole trace stays: frames come after all samples here
  EnergyLedger ledger(o);
  for (const TraceEvent& e : trace.events) {
    if (e.lost) ledger.meterLost("meter gap (recorded)");
    else ledger.addSample(e.sample);
  }
  for (const FrameInterval& f : frames) ledger.addFrame(f);
  OfflineResult r;
  r.frames = ledger.finish("no power sample after the frame's end in the trace");
  r.totals = ledger.totals();
  return r;
}

}  // namespace sb::power
