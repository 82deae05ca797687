#include "tests/ros/bag_writer.h"

#include <rosbag/bag.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "drivers/sequence.h"
#include "drivers/tum_writer.h"

namespace sb::test::ros_e2e {

namespace {

constexpr double kMillimetres = 1000.0;
constexpr double kRecordDelayS = 0.01;

std::unique_ptr<FrameSource> openPlain(const std::string& sequence) {
  SequenceOptions o;
  o.prefetch = false;
  return openSequence(sequence, o);
}

}  // namespace

size_t writeBag(const std::string& bagPath, const std::string& sequence, const BagSpec& spec) {
  auto source = openPlain(sequence);
  const SequenceInfo info = source->info();
  if (spec.encoding == "16UC1" && info.depthScale != kMillimetres)
    throw std::runtime_error("a 16UC1 bag needs a millimetre sequence");
  rosbag::Bag bag(bagPath, rosbag::bagmode::Write);
  size_t n = 0;
  while (auto f = source->next()) {
    const ros::Time stamp(f->timestamp);
    // When the recorder received it: a little later, and after ros::TIME_MIN (a synthetic frame 0 is at 0 s).
    const ros::Time recorded = stamp + ros::Duration(kRecordDelayS);
    sensor_msgs::Image image;
    image.header.stamp = stamp;
    image.header.seq = static_cast<uint32_t>(n);
    image.header.frame_id = "openni_depth_optical_frame";
    image.width = static_cast<uint32_t>(f->depth.width());
    image.height = static_cast<uint32_t>(f->depth.height());
    image.encoding = spec.encoding;
    if (spec.encoding == "32FC1") {
      image.step = image.width * sizeof(float);
      image.data.resize(static_cast<size_t>(image.step) * image.height);
      for (size_t i = 0; i < f->depth.size(); ++i) {
        const uint16_t raw = f->depth.pixels()[i];
        const float m = raw ? static_cast<float>(raw / info.depthScale) : std::numeric_limits<float>::quiet_NaN();
        std::memcpy(image.data.data() + i * sizeof(float), &m, sizeof m);
      }
    } else {
      image.step = image.width * sizeof(uint16_t);
      image.data.resize(static_cast<size_t>(image.step) * image.height);
      std::memcpy(image.data.data(), f->depth.data(), image.data.size());
    }
    bag.write(kBagDepthTopic, recorded, image);
    if (spec.cameraInfo) {
      sensor_msgs::CameraInfo ci;
      ci.header = image.header;
      ci.width = image.width;
      ci.height = image.height;
      ci.K = {info.intrinsics.fx, 0, info.intrinsics.cx, 0, info.intrinsics.fy, info.intrinsics.cy, 0, 0, 1};
      bag.write("/camera/depth/camera_info", recorded, ci);
    }
    if (spec.rgbTopic) {
      sensor_msgs::Image rgb;
      rgb.header = image.header;
      rgb.width = 4;
      rgb.height = 4;
      rgb.encoding = "rgb8";
      rgb.step = 12;
      rgb.data.assign(48, 128);
      bag.write(kBagRgbTopic, recorded, rgb);
    }
    ++n;
  }
  bag.close();
  return n;
}

void writeMillimetreCopy(const std::string& sequence, const std::string& directory) {
  auto source = openPlain(sequence);
  SequenceInfo info = source->info();
  const double scale = info.depthScale;
  info.depthScale = kMillimetres;
  TumSequenceWriter writer(directory, info);
  while (auto f = source->next()) {
    for (auto& v : f->depth.pixels()) v = static_cast<uint16_t>(std::lround(v * kMillimetres / scale));
    writer.write(*f);
  }
  writer.finish();
}

}  // namespace sb::test::ros_e2e
