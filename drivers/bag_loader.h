#pragma once
// Finds and loads the bag plugin (drivers/bag_plugin.h) on first use and keeps it loaded for the process's
// life. Where: beside a build tree's executables the build tree's plugin, else the installed one
// (<prefix>/lib/slambooster). A missing plugin is an error that says which package to install.

#include <memory>
#include <string>
#include <vector>

#include "drivers/frame_source.h"
#include "drivers/sequence.h"
#include "drivers/odometry_sample.h"

namespace sb {

// Throws sb::Error when the plugin is not installed, does not load, or is of another version; otherwise
// whatever the plugin throws for this bag.
std::unique_ptr<FrameSource> openBag(const std::string& path, const SequenceOptions& options);
// The bag's odometry (SbReadBagOdometryFn of drivers/bag_plugin.h); `source` (may be null) says which topic
// and camera mount. Throws as openBag does.
std::vector<odometry::OdometrySample> readBagOdometry(const std::string& path, const std::string& topic,
                                                     const std::string& cameraMount, std::string* source);

}  // namespace sb
