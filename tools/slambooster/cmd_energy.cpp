// `slambooster energy`: re-accounts a recorded run offline. Reads the raw power trace written beside the
// per-frame log (power/power_trace.h) and the run's frames.jsonl (per-frame CLOCK_MONOTONIC start/end), and
// prints per-run energy; optionally writes per-frame joules.

#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "power/energy_json.h"
#include "power/offline_accounting.h"
#include "power/power_trace.h"
#include "tools/slambooster/commands.h"

namespace sb::cli {

namespace {

struct EnergyOptions {
  std::string trace;
  std::string frames;
  std::string out;
  double idleWatts = 0.0;
  double maxGapMs = 0.0;
  bool json = false;
};

void energyCommand(const EnergyOptions& o) {
  const power::PowerTrace trace = power::readPowerTrace(o.trace);
  const std::vector<power::FrameInterval> frames = power::readFrameIntervals(o.frames);
  if (frames.empty()) throw Error("frame log '" + o.frames + "' holds no frames");
  power::OfflineOptions options;
  options.idleWatts = o.idleWatts;
  options.maxSampleGapNs = static_cast<int64_t>(std::llround(o.maxGapMs * 1e6));
  const power::OfflineResult r = power::accountOffline(trace, frames, options);
  const power::EnergyTotals& t = r.totals;

  std::map<std::string, size_t> reasons;
  for (const power::FrameEnergy& e : r.frames)
    if (!e.known) ++reasons[e.unknownReason];

  if (!o.out.empty()) {
    std::ofstream out(o.out);
    if (!out) throw Error("cannot write '" + o.out + "'");
    for (const power::FrameEnergy& e : r.frames) out << power::frameEnergyJson(e).dump() << "\n";
  }

  if (o.json) {
    nlohmann::json j = {{"class", "ENERGY_SUMMARY"},
                        {"meter", trace.meter.name},
                        {"device", trace.meter.device},
                        {"sample_kind", power::sampleKindName(trace.meter.kind)},
                        {"samples", trace.events.size()}};
    j.update(power::energyTotalsJson(t, reasons));
    std::cout << j.dump(2) << "\n";
    return;
  }
  std::cout << std::fixed << std::setprecision(3);
  std::cout << "trace: " << trace.meter.name << " (" << trace.meter.device << "), " << trace.events.size()
            << " events, " << power::sampleKindName(trace.meter.kind) << " samples\n";
  std::cout << "frames " << t.frames << ": energy known for " << t.knownFrames << ", unknown for " << t.unknownFrames
            << "\n";
  for (const auto& [reason, count] : reasons) std::cout << "  unknown: " << count << " x " << reason << "\n";
  if (t.knownFrames > 0) {
    std::cout << "frames: " << t.joules << " J over " << t.seconds << " s = " << t.meanWatts() << " W mean, "
              << t.joulesPerFrame() << " J/frame\n";
    if (t.idleWatts != 0.0)
      std::cout << "above idle (" << t.idleWatts << " W): " << t.joulesAboveIdle << " J, "
                << t.joulesAboveIdle / static_cast<double>(t.knownFrames) << " J/frame\n";
  }
  std::cout << "run span " << t.spanSeconds << " s (" << t.spanKnownSeconds << " s measured): " << t.spanJoules
            << " J";
  if (t.spanKnownSeconds > 0) std::cout << " = " << t.spanMeanWatts() << " W mean";
  std::cout << "\n";
  if (!o.out.empty()) std::cout << "per-frame energy in " << o.out << "\n";
}

}  // namespace

void addEnergyCommand(CLI::App& app) {
  auto options = std::make_shared<EnergyOptions>();
  auto* sub = app.add_subcommand("energy", "Re-account a recorded run: joules per frame from its power trace");
  sub->add_option("--trace", options->trace, "Power trace (CSV) recorded beside the per-frame log")->required();
  sub->add_option("--frames", options->frames, "The run's frames.jsonl (needs t_start_mono_ns, t_end_mono_ns)")
      ->required();
  sub->add_option("--out", options->out, "Write per-frame energy as JSON lines to this file");
  sub->add_option("--idle-watts", options->idleWatts, "Idle baseline (W) subtracted in the 'above idle' numbers")
      ->check(CLI::Range(0.0, 10000.0));
  sub->add_option("--max-gap-ms", options->maxGapMs,
                  "Samples farther apart enclose a gap (0 = 3 meter periods, at least 1500 ms)")
      ->check(CLI::Range(0.0, 3.6e6));
  sub->add_flag("--json", options->json, "Print the summary as JSON");
  sub->callback([options] { energyCommand(*options); });
}

}  // namespace sb::cli
