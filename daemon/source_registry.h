#pragma once
// Frame sources by name (config key source.type). Adding a source: one file pair implementing
// CaptureSource (constructed from the SourceConfig) plus one line in source_registry.cpp; a new setting is a
// key of the source section (source_config.h).

#include <memory>
#include <string>
#include <vector>

#include "daemon/capture_source.h"
#include "daemon/daemon_config.h"

namespace sb::daemon {

std::vector<std::string> sourceTypes();
// Throws sb::Error naming an unknown type (and listing the known ones) or the source's own failure.
std::unique_ptr<CaptureSource> createSource(const SourceConfig& config);

}  // namespace sb::daemon
