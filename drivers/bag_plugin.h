#pragma once
// The bag-file frame source lives in a plugin (libslambooster_bag.so, built from ros/ only where ROS 1's
// rosbag is installed) so that neither slamboosterd nor slambooster links ROS: openSequence() loads it with
// dlopen when it is given a `.bag` path (drivers/bag_loader.h). This header is the whole contract between the
// two; both sides are built from the same tree with the same compiler, so C++ types cross it.

#include <memory>
#include <string>

#include "drivers/frame_source.h"
#include "drivers/sequence.h"

namespace sb {

// Bumped whenever FrameSource, DepthFrame, SequenceInfo, SequenceOptions or this signature change; a plugin of
// another version is refused with an error saying so.
inline constexpr int kBagPluginAbi = 1;

extern "C" {
// The plugin's ABI version (kBagPluginAbi when it was built).
using SbBagPluginAbiFn = int (*)();
// Opens a bag: like openSequence() (throws sb::Error naming the file or topic); the caller owns the result.
using SbOpenBagFn = FrameSource* (*)(const std::string& path, const SequenceOptions& options);
}

inline constexpr const char* kBagPluginFile = "libslambooster_bag.so";
inline constexpr const char* kBagPluginAbiSymbol = "sbBagPluginAbi";
inline constexpr const char* kBagPluginOpenSymbol = "sbOpenBag";

}  // namespace sb
