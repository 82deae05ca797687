#include "daemon/source_registry.h"

#include <functional>

#include "core/error.h"
#include "daemon/openni2_capture.h"
#include "daemon/pattern_source.h"
#include "daemon/push_source.h"
#include "daemon/replay_source.h"

namespace sb::daemon {

namespace {

struct SourceEntry {
  const char* type;
  std::function<std::unique_ptr<CaptureSource>(const SourceConfig&)> create;
};

const std::vector<SourceEntry>& registry() {
  static const std::vector<SourceEntry> entries = {
      {"replay", [](const SourceConfig& c) { return std::make_unique<ReplaySource>(c); }},
      {"openni2", [](const SourceConfig& c) { return std::make_unique<OpenNI2Capture>(c); }},
      {"pattern", [](const SourceConfig& c) { return std::make_unique<PatternSource>(c); }},
      {"push", [](const SourceConfig& c) { return std::make_unique<PushSource>(c); }},
  };
  return entries;
}

}  // namespace

std::vector<std::string> sourceTypes() {
  std::vector<std::string> names;
  for (const auto& e : registry()) names.emplace_back(e.type);
  return names;
}

std::unique_ptr<CaptureSource> createSource(const SourceConfig& config) {
  for (const auto& e : registry())
    if (config.type == e.type) return e.create(config);
  std::string known;
  for (const auto& n : sourceTypes()) known += (known.empty() ? "" : ", ") + n;
  throw Error("source.type = \"" + config.type + "\" is not a known source (known: " + known + ")");
}

}  // namespace sb::daemon
