#include "ros/bag_source.h"

#include <rosbag/exceptions.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <set>

#include "core/error.h"
#include "drivers/bag_plugin.h"
#include "ros/depth_image.h"

namespace sb::ros_bridge {

namespace {

constexpr const char* kImageType = "sensor_msgs/Image";
constexpr const char* kCameraInfoType = "sensor_msgs/CameraInfo";

// The camera_info topic beside an image topic: same namespace, last name replaced.
std::string cameraInfoTopicFor(const std::string& imageTopic) {
  const auto slash = imageTopic.rfind('/');
  return (slash == std::string::npos ? std::string() : imageTopic.substr(0, slash + 1)) + "camera_info";
}

std::string list(const std::set<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "none" : out;
}

// Everything rosbag or the message deserialiser may throw becomes an sb::Error naming `where`.
template <typename F>
auto guarded(const std::string& where, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(where + ": " + e.what() + " (a truncated or damaged bag?)");
  }
}

}  // namespace

BagSource::BagSource(const std::string& path, const SequenceOptions& options)
    : path_(path), firstFrame_(options.firstFrame), maxFrames_(options.maxFrames) {
  try {
    bag_.open(path, rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    throw Error("cannot read ROS bag '" + path + "': " + e.what() +
                " (a truncated or damaged file? `rosbag reindex` repairs an unindexed one)");
  }
  topic_ = chooseDepthTopic(options.depthTopic);

  view_ = guarded("bag '" + path_ + "'", [&] { return std::make_unique<rosbag::View>(bag_, rosbag::TopicQuery(topic_)); });
  const size_t messages = view_->size();
  if (messages == 0) throw Error("bag '" + path_ + "': topic '" + topic_ + "' has no messages");
  // The first frame decides the depth scale (unless given) and is checked before any frame is processed.
  const auto first = guarded(where(0), [&] { return view_->begin()->instantiate<sensor_msgs::Image>(); });
  if (!first) throw Error(where(0) + ": not a sensor_msgs/Image");
  info_.depthScale = options.depthScale ? *options.depthScale : defaultDepthScale(first->encoding);
  (void)toDepthRaw(*first, info_.depthScale, where(0));  // the encoding before anything else
  readIntrinsics(cameraInfoTopicFor(topic_), options);
  if (static_cast<int>(first->width) != info_.intrinsics.width ||
      static_cast<int>(first->height) != info_.intrinsics.height)
    throw Error(where(0) + ": image " + std::to_string(first->width) + "x" + std::to_string(first->height) +
                " differs from the camera_info's " + std::to_string(info_.intrinsics.width) + "x" +
                std::to_string(info_.intrinsics.height));

  info_.path = path_;
  info_.format = "rosbag";
  const size_t available = messages > firstFrame_ ? messages - firstFrame_ : 0;
  info_.frameCount = maxFrames_ > 0 ? std::min(maxFrames_, available) : available;
  it_ = view_->begin();
}

std::string BagSource::where(size_t message) const {
  return "bag '" + path_ + "' topic '" + topic_ + "' message " + std::to_string(message);
}

std::string BagSource::chooseDepthTopic(const std::string& requested) const {
  rosbag::View all(bag_);
  std::set<std::string> images, depthImages;
  std::string requestedType;
  for (const rosbag::ConnectionInfo* c : all.getConnections()) {
    if (c->topic == requested) requestedType = c->datatype;
    if (c->datatype == kImageType) images.insert(c->topic);
  }
  if (!requested.empty()) {
    if (requestedType.empty())
      throw Error("bag '" + path_ + "' has no topic '" + requested + "' (its sensor_msgs/Image topics: " +
                  list(images) + ")");
    if (requestedType != kImageType)
      throw Error("bag '" + path_ + "': topic '" + requested + "' holds " + requestedType + ", not " + kImageType);
    return requested;
  }
  for (const auto& topic : images) {  // an image topic is a depth topic when its first message says so
    rosbag::View v(bag_, rosbag::TopicQuery(topic));
    const auto m = guarded("bag '" + path_ + "' topic '" + topic + "'",
                           [&] { return v.begin()->instantiate<sensor_msgs::Image>(); });
    if (m && isDepthEncoding(m->encoding)) depthImages.insert(topic);
  }
  if (depthImages.size() == 1) return *depthImages.begin();
  if (depthImages.empty())
    throw Error("bag '" + path_ + "' has no depth image topic (16UC1 or 32FC1 sensor_msgs/Image; its image topics: " +
                list(images) + "): name one with --depth-topic");
  throw Error("bag '" + path_ + "' has several depth image topics (" + list(depthImages) +
              "): choose one with --depth-topic");
}

void BagSource::readIntrinsics(const std::string& cameraInfoTopic, const SequenceOptions& options) {
  const bool given = options.fx && options.fy && options.cx && options.cy && options.width && options.height;
  rosbag::View v(bag_, rosbag::TopicQuery(cameraInfoTopic));
  if (v.size() == 0) {
    if (!given)
      throw Error("bag '" + path_ + "' has no " + kCameraInfoType + " on '" + cameraInfoTopic +
                  "' (beside the depth topic '" + topic_ + "'): record it, or give the intrinsics as options");
  } else {
    const std::string where = "bag '" + path_ + "' topic '" + cameraInfoTopic + "' message 0";
    const auto m = guarded(where, [&] { return v.begin()->instantiate<sensor_msgs::CameraInfo>(); });
    if (!m) throw Error(where + ": not a " + std::string(kCameraInfoType));
    info_.intrinsics = toIntrinsics(*m, where);
  }
  if (options.fx) info_.intrinsics.fx = *options.fx;
  if (options.fy) info_.intrinsics.fy = *options.fy;
  if (options.cx) info_.intrinsics.cx = *options.cx;
  if (options.cy) info_.intrinsics.cy = *options.cy;
  if (options.width) info_.intrinsics.width = *options.width;
  if (options.height) info_.intrinsics.height = *options.height;
}

std::optional<DepthFrame> BagSource::next() {
  while (true) {
    if (maxFrames_ > 0 && emitted_ >= maxFrames_) return std::nullopt;
    const size_t index = message_;
    const bool atEnd = guarded(where(index), [&] { return it_ == view_->end(); });
    if (atEnd) return std::nullopt;
    const auto image = guarded(where(index), [&] { return it_->instantiate<sensor_msgs::Image>(); });
    guarded(where(index), [&] { ++it_; return 0; });
    ++message_;
    if (index < firstFrame_) continue;
    if (!image) throw Error(where(index) + ": not a sensor_msgs/Image");
    DepthFrame f;
    f.index = index;
    f.timestamp = image->header.stamp.toSec();  // the capture time (the bag's own time is when it was recorded)
    f.depth = toDepthRaw(*image, info_.depthScale, where(index));
    if (f.depth.width() != info_.intrinsics.width || f.depth.height() != info_.intrinsics.height)
      throw Error(where(index) + ": image " + std::to_string(f.depth.width()) + "x" +
                  std::to_string(f.depth.height()) + " differs from the sequence's " +
                  std::to_string(info_.intrinsics.width) + "x" + std::to_string(info_.intrinsics.height));
    ++emitted_;
    return f;
  }
}

}  // namespace sb::ros_bridge

// The plugin's entry points (drivers/bag_plugin.h).
extern "C" __attribute__((visibility("default"))) int sbBagPluginAbi() { return sb::kBagPluginAbi; }

extern "C" __attribute__((visibility("default"))) sb::FrameSource* sbOpenBag(const std::string& path,
                                                                              const sb::SequenceOptions& options) {
  return new sb::ros_bridge::BagSource(path, options);
}
