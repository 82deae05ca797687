#include "power/power_trace.h"

#include <spdlog/spdlog.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/input_file.h"

namespace sb::power {

namespace {

constexpr const char* kFormat = "slambooster-power-trace";
constexpr const char* kColumns = "t_ns,watts,volts,amps,event";

// Shortest text that reads back as the same double; empty for NaN.
std::string number(double v) {
  if (std::isnan(v)) return "";
  char buffer[64];
  const auto r = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, r.ptr);
}

std::string traceHeader(const MeterInfo& meter) {
  const nlohmann::json header = {{"format", kFormat},
                                 {"version", 1},
                                 {"meter", meter.name},
                                 {"device", meter.device},
                                 {"kind", sampleKindName(meter.kind)},
                                 {"nominal_period_ns", meter.nominalPeriodNs},
                                 {"clock", "CLOCK_MONOTONIC"}};
  return "# " + header.dump() + "\n" + kColumns + "\n";
}

constexpr size_t kMaxPendingBytes = 64 * 1024;  // lines held between two flushes at most

}  // namespace

PowerTraceWriter::PowerTraceWriter(const std::string& path, const MeterInfo& meter,
                                   std::shared_ptr<SegmentStore> segments)
    : file_(std::filesystem::path(path).parent_path().string().empty()
                ? std::string(".")
                : std::filesystem::path(path).parent_path().string(),
            std::filesystem::path(path).filename().string(), "power trace", traceHeader(meter),
            std::move(segments)) {}

PowerTraceWriter::~PowerTraceWriter() {
  flush();
}

void PowerTraceWriter::sample(const PowerSample& s) {
  pending_ += std::to_string(static_cast<long long>(s.tNs)) + "," + number(s.watts) + "," + number(s.volts) +
              "," + number(s.amps) + "," + (s.gapBefore ? "gap" : "") + "\n";
  if (pending_.size() > kMaxPendingBytes) flush();
}

void PowerTraceWriter::lost(int64_t tNs) {
  pending_ += std::to_string(static_cast<long long>(tNs)) + ",,,,lost\n";
  if (pending_.size() > kMaxPendingBytes) flush();
}

void PowerTraceWriter::flush() {
  if (pending_.empty()) return;
  try {
    file_.append(pending_);
    failing_ = false;
  } catch (const Error& e) {
    if (!failing_) spdlog::error("{}; the trace misses samples until a write succeeds", e.what());
    failing_ = true;
  }
  pending_.clear();
}

PowerTrace readPowerTrace(const std::string& path) {
  InputFile in(path, "power trace");
  PowerTrace trace;
  std::string line;
  size_t lineNo = 0;
  auto fail = [&](const std::string& what) -> Error {
    return Error("power trace '" + path + "' line " + std::to_string(lineNo) + ": " + what);
  };
  if (!std::getline(in, line) || line.rfind("# ", 0) != 0) {
    lineNo = 1;
    throw fail("expected the header '# {\"format\":\"slambooster-power-trace\",...}'");
  }
  ++lineNo;
  try {
    const auto header = nlohmann::json::parse(line.substr(2));
    if (header.at("format") != kFormat || header.at("version") != 1) throw fail("not a version 1 power trace");
    trace.meter.name = header.at("meter").get<std::string>();
    trace.meter.device = header.at("device").get<std::string>();
    trace.meter.kind = parseSampleKind(header.at("kind").get<std::string>(), path);
    trace.meter.nominalPeriodNs = header.at("nominal_period_ns").get<int64_t>();
  } catch (const nlohmann::json::exception& e) {
    throw fail(std::string("bad header: ") + e.what());
  }
  if (!std::getline(in, line) || line != kColumns) {
    ++lineNo;
    throw fail(std::string("expected the column line '") + kColumns + "'");
  }
  ++lineNo;
  int64_t lastNs = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    if (line.empty()) continue;
    std::vector<std::string> f;
    size_t start = 0;
    for (;;) {
      const size_t comma = line.find(',', start);
      f.push_back(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    if (f.size() != 5) throw fail("expected 5 fields (t_ns,watts,volts,amps,event), got " + std::to_string(f.size()));
    auto toDouble = [&](const std::string& text, const char* what, bool optional) {
      if (text.empty()) {
        if (optional) return NAN * 1.0;
        throw fail(std::string("missing ") + what);
      }
      double v = 0;
      const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
      if (r.ec != std::errc() || r.ptr != text.data() + text.size()) throw fail(std::string("bad ") + what + " '" + text + "'");
      return v;
    };
    TraceEvent e;
    long long t = 0;
    const auto r = std::from_chars(f[0].data(), f[0].data() + f[0].size(), t);
    if (r.ec != std::errc() || r.ptr != f[0].data() + f[0].size()) throw fail("bad t_ns '" + f[0] + "'");
    e.sample.tNs = t;
    if (e.sample.tNs < lastNs) throw fail("time goes backwards");
    lastNs = e.sample.tNs;
    if (f[4] == "lost") {
      e.lost = true;
    } else if (f[4].empty() || f[4] == "gap") {
      e.sample.watts = toDouble(f[1], "watts", false);
      e.sample.volts = toDouble(f[2], "volts", true);
      e.sample.amps = toDouble(f[3], "amps", true);
      e.sample.gapBefore = f[4] == "gap";
    } else {
      throw fail("unknown event '" + f[4] + "' (expected empty, gap or lost)");
    }
    trace.events.push_back(e);
  }
  return trace;
}

}  // namespace sb::power
