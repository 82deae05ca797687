#pragma once
// A dense row-major 2D image that owns its pixels.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sb {

// Largest depth-image side accepted from any file, header, calibration or option, pixels: a corrupt or hostile
// header must not make us allocate gigabytes (an 8192x8192 frame of 151 KB took 2.5 GB through the pipeline
// as the first frame of a sequence without calibration). Depth cameras stay far below: Kinect v1/v2, Azure
// Kinect and RealSense at most 1280x1024, stereo cameras about 2208x1242.
constexpr int kMaxDepthImageSide = 4096;

template <typename T>
class Image {
 public:
  Image() = default;
  Image(int width, int height, T fill = T{})
      : width_(width), height_(height), data_(static_cast<size_t>(width) * height, fill) {}

  int width() const { return width_; }
  int height() const { return height_; }
  size_t size() const { return data_.size(); }
  bool empty() const { return data_.empty(); }

  T& operator()(int x, int y) { return data_[static_cast<size_t>(y) * width_ + x]; }
  const T& operator()(int x, int y) const { return data_[static_cast<size_t>(y) * width_ + x]; }
  T* data() { return data_.data(); }
  const T* data() const { return data_.data(); }
  std::vector<T>& pixels() { return data_; }
  const std::vector<T>& pixels() const { return data_; }

  void resize(int width, int height, T fill = T{}) {
    width_ = width;
    height_ = height;
    data_.assign(static_cast<size_t>(width) * height, fill);
  }

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<T> data_;
};

using DepthRaw = Image<uint16_t>;  // sensor units (see SequenceInfo::depthScale); 0 = no reading
using DepthMeters = Image<float>;  // metres; 0 = no reading

}  // namespace sb
