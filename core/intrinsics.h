#pragma once
// Pinhole camera intrinsics in pixels, for an image of width x height.

namespace sb {

struct Intrinsics {
  int width = 640;   // pixels
  int height = 480;  // pixels
  float fx = 0.f;    // focal length x, pixels
  float fy = 0.f;    // focal length y, pixels
  float cx = 0.f;    // principal point x, pixels
  float cy = 0.f;    // principal point y, pixels

  // Intrinsics of the image subsampled by `ratio` (1, 2, 4, 8), pixel centres kept consistent with a
  // block-average subsampling (KinectFusion's convention: focal and centre divided by the ratio).
  Intrinsics scaled(int ratio) const {
    Intrinsics k = *this;
    k.width = width / ratio;
    k.height = height / ratio;
    k.fx = fx / ratio;
    k.fy = fy / ratio;
    k.cx = cx / ratio;
    k.cy = cy / ratio;
    return k;
  }
};

}  // namespace sb
