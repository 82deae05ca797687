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

template <typename Source>
std::unique_ptr<CaptureSource> create(const SourceConfig& config) {
  return std::make_unique<Source>(config);
}

// One line per source; its settings are keys of the source section (source_config.h).
const std::vector<SourceEntry>& registry() {
  static const std::vector<SourceEntry> entries = {
      {"replay", create<ReplaySource>},
      {"openni2", create<OpenNI2Capture>},
      {"pattern", create<PatternSource>},
      {"push", create<PushSource>},
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
