#pragma once
// The bag-file frame source lives in a plugin (libslambooster_bag.so, built from ros/ only where ROS 1's
// rosbag is installed) so that neither slamboosterd nor slambooster links ROS: openSequence() loads it with
// dlopen when it is given a `.bag` path (drivers/bag_loader.h). This header is the whole contract between the
// two; both sides are built from the same tree with the same compiler, so C++ types cross it.

#include <memory>
#include <string>
#include <vector>

#include "drivers/frame_source.h"
#include "drivers/sequence.h"
#include "drivers/odometry_sample.h"

namespace sb {

// Bumped whenever FrameSource, DepthFrame, SequenceInfo, SequenceOptions, OdometrySample or these signatures
// change; a plugin of another version is refused with an error saying so. 2: sbReadBagOdometry.
inline constexpr int kBagPluginAbi = 2;

extern "C" {
// The plugin's ABI version (kBagPluginAbi when it was built).
using SbBagPluginAbiFn = int (*)();
// Opens a bag: like openSequence() (throws sb::Error naming the file or topic); the caller owns the result.
using SbOpenBagFn = FrameSource* (*)(const std::string& path, const SequenceOptions& options);
// Reads a bag's nav_msgs/Odometry on `topic` (empty: the bag's only Odometry topic; none: no samples) composed
// with the camera mount (`cameraMount` "x y z qx qy qz qw", or the bag's /tf_static from the messages' child
// frame to the depth images' frame): T_camera_to_odom samples, stamps on the depth frames' clock. `source`
// says which topic and mount. Throws sb::Error naming the bag, topic or transform.
using SbReadBagOdometryFn = void (*)(const std::string& path, const std::string& topic,
                                     const std::string& cameraMount, std::vector<odometry::OdometrySample>& out,
                                     std::string& source);
}

inline constexpr const char* kBagPluginFile = "libslambooster_bag.so";
inline constexpr const char* kBagPluginAbiSymbol = "sbBagPluginAbi";
inline constexpr const char* kBagPluginOpenSymbol = "sbOpenBag";
inline constexpr const char* kBagPluginOdometrySymbol = "sbReadBagOdometry";

}  // namespace sb
