#pragma once
// A ROS 1 bag as a frame source (the bag plugin, drivers/bag_plugin.h): depth from one sensor_msgs/Image
// topic (16UC1 mm or 32FC1 m), intrinsics from the first sensor_msgs/CameraInfo on the camera_info topic
// beside it (/camera/depth/image -> /camera/depth/camera_info, as in TUM RGB-D's bags) unless the options
// give them. Read with the rosbag C++ API in the bag's time order.

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <memory>
#include <string>

#include "drivers/frame_source.h"
#include "drivers/sequence.h"

namespace sb::ros_bridge {

class BagSource : public FrameSource {
 public:
  // Opens the bag and checks the topics and the first frame. Throws sb::Error naming the file and topic.
  BagSource(const std::string& path, const SequenceOptions& options);

  const SequenceInfo& info() const override { return info_; }
  std::optional<DepthFrame> next() override;

 private:
  std::string chooseDepthTopic(const std::string& requested) const;
  void readIntrinsics(const std::string& cameraInfoTopic, const SequenceOptions& options);
  std::string where(size_t message) const;

  std::string path_;
  std::string topic_;
  rosbag::Bag bag_;
  std::unique_ptr<rosbag::View> view_;
  rosbag::View::iterator it_;
  SequenceInfo info_;
  size_t message_ = 0;   // messages of the depth topic read so far
  size_t emitted_ = 0;   // frames returned
  size_t firstFrame_ = 0;
  size_t maxFrames_ = 0;
};

}  // namespace sb::ros_bridge
