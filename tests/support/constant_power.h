#pragma once
// A power meter for end-to-end tests: a recorded trace of constant power at 200 Hz over 300 s (power_trace.h
// format) and a power config whose "file" meter replays it live, so every frame's joules must be
// watts x its processing interval.

#include <cstdint>
#include <fstream>
#include <string>

namespace sb::test {

// Writes DIR/trace.csv and DIR/power.json; returns the power.json path.
inline std::string writeConstantPowerMeter(const std::string& dir, double watts) {
  {
    std::ofstream trace(dir + "/trace.csv");
    trace << R"(# {"format":"slambooster-power-trace","version":1,"meter":"smartpower3","device":"recorded",)"
          << R"("kind":"instantaneous","nominal_period_ns":5000000,"clock":"CLOCK_MONOTONIC"})" << "\n"
          << "t_ns,watts,volts,amps,event\n";
    for (int64_t i = 0; i < 200 * 300; ++i) trace << 1000000000 + i * 5000000 << "," << watts << ",5,0.9,\n";
  }
  std::ofstream(dir + "/power.json") << R"({"meter": "file", "file": {"path": ")" << dir << R"(/trace.csv"}})";
  return dir + "/power.json";
}

}  // namespace sb::test
