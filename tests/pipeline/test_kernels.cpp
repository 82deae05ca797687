// Each preprocessing kernel against an independent expectation.

#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "kernels/preprocess.h"
#include "kernels/volume.h"
#include "pipeline/cpu/cpu_backend.h"

namespace {

std::vector<float> gaussian(int radius, float sigma) {
  std::vector<float> g;
  for (int i = -radius; i <= radius; ++i) g.push_back(std::exp(-float(i * i) / (2 * sigma * sigma)));
  return g;
}

}  // namespace

TEST_CASE("mm2meters scales, subsamples and keeps invalid pixels at 0", "[pipeline][kernels]") {
  const int w = 8, h = 4;
  std::vector<unsigned short> raw(w * h);
  for (int i = 0; i < w * h; ++i) raw[i] = static_cast<unsigned short>(i % 3 == 0 ? 0 : 1000 + 7 * i);
  std::vector<float> out(w * h, -1.f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) mm2meters(out.data(), w, raw.data(), w, 1, 1e-3f, x, y);
  for (int i = 0; i < w * h; ++i) CHECK(out[i] == Approx(raw[i] * 1e-3).epsilon(1e-6));
  CHECK(out[0] == 0.0f);
  // Ratio 2: the top-left pixel of each 2x2 block.
  std::vector<float> half((w / 2) * (h / 2), -1.f);
  for (int y = 0; y < h / 2; ++y)
    for (int x = 0; x < w / 2; ++x) mm2meters(half.data(), w / 2, raw.data(), w, 2, 0.2e-3f, x, y);
  for (int y = 0; y < h / 2; ++y)
    for (int x = 0; x < w / 2; ++x) CHECK(half[y * (w / 2) + x] == Approx(raw[2 * y * w + 2 * x] * 0.2e-3).epsilon(1e-6));
}

TEST_CASE("bilateralFilter is the identity on a constant image and leaves holes empty", "[pipeline][kernels]") {
  const int w = 12, h = 9;
  std::vector<float> in(w * h, 1.7f), out(w * h, -1.f);
  in[5 * w + 6] = 0.0f;  // a hole
  const auto g = gaussian(2, 4.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) bilateralFilter(out.data(), in.data(), w, h, g.data(), 2, 0.1f, x, y);
  for (int i = 0; i < w * h; ++i) {
    if (i == 5 * w + 6)
      CHECK(out[i] == 0.0f);
    else
      CHECK(out[i] == Approx(1.7f).epsilon(1e-6));
  }
}

TEST_CASE("bilateralFilter preserves a depth edge much larger than the range sigma", "[pipeline][kernels]") {
  const int w = 10, h = 6;
  std::vector<float> in(w * h), out(w * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) in[y * w + x] = x < 5 ? 1.0f : 2.0f;
  const auto g = gaussian(2, 4.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) bilateralFilter(out.data(), in.data(), w, h, g.data(), 2, 0.1f, x, y);
  // The far side's weight is exp(-1/(2*0.01)) ~ 2e-22 relative: the edge stays sharp.
  CHECK(out[2 * w + 4] == Approx(1.0f).epsilon(1e-5));
  CHECK(out[2 * w + 5] == Approx(2.0f).epsilon(1e-5));
}

TEST_CASE("halfSampleRobust averages within 0.3 m of the block's first pixel and rejects the rest",
          "[pipeline][kernels]") {
  const int w = 4, h = 2;
  // Block 0: 1.0, 1.2, 1.25, 1.5 (1.5 is 0.5 m away -> rejected). Block 1: 2.0, 2.29, 0 (hole), 2.31.
  std::vector<float> in = {1.0f, 1.2f, 2.0f, 2.29f, 1.25f, 1.5f, 0.0f, 2.31f};
  std::vector<float> out(2, -1.f);
  for (int x = 0; x < 2; ++x) halfSampleRobust(out.data(), 2, in.data(), w, h, 0.3f, x, 0);
  CHECK(out[0] == Approx((1.0 + 1.2 + 1.25) / 3).epsilon(1e-6));
  CHECK(out[1] == Approx((2.0 + 2.29) / 2).epsilon(1e-6));  // 2.31 is > 0.3 from 2.0, the hole is skipped
}

TEST_CASE("a plane gives exact vertices and a constant normal", "[pipeline][kernels]") {
  const int w = 16, h = 12;
  const SbCamera k{20.0f, 22.0f, 7.5f, 5.5f};
  // Plane n.X = d with n = (0.3, -0.2, -0.93), seen from the origin.
  const float nx = 0.3f, ny = -0.2f, nz = -std::sqrt(1 - 0.09f - 0.04f), d = -1.5f;
  std::vector<float> depth(w * h), vertex(3 * w * h), normal(3 * w * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float rx = (x - k.cx) / k.fx, ry = (y - k.cy) / k.fy;
      depth[y * w + x] = d / (nx * rx + ny * ry + nz);  // ray (rx, ry, 1) * z hits the plane
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) depth2vertex(vertex.data(), depth.data(), w, k, x, y);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) vertex2normal(normal.data(), vertex.data(), w, h, x, y);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int i = y * w + x;
      const float z = depth[i];
      CHECK(vertex[3 * i] == Approx(z * (x - k.cx) / k.fx).epsilon(1e-6));
      CHECK(vertex[3 * i + 1] == Approx(z * (y - k.cy) / k.fy).epsilon(1e-6));
      CHECK(vertex[3 * i + 2] == z);
      CHECK(nx * vertex[3 * i] + ny * vertex[3 * i + 1] + nz * vertex[3 * i + 2] == Approx(d).epsilon(1e-5));
      // Normals point towards the camera: the plane's normal with n.z < 0.
      CHECK(normal[3 * i] == Approx(nx).margin(1e-4));
      CHECK(normal[3 * i + 1] == Approx(ny).margin(1e-4));
      CHECK(normal[3 * i + 2] == Approx(nz).margin(1e-4));
    }
}

TEST_CASE("vertex2normal marks pixels next to a hole invalid", "[pipeline][kernels]") {
  const int w = 5, h = 5;
  std::vector<float> vertex(3 * w * h), normal(3 * w * h);
  for (int i = 0; i < w * h; ++i) {
    vertex[3 * i] = float(i % w);
    vertex[3 * i + 1] = float(i / w);
    vertex[3 * i + 2] = (i == 12) ? 0.0f : 2.0f;
  }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) vertex2normal(normal.data(), vertex.data(), w, h, x, y);
  for (int i : {7, 11, 12, 13, 17}) CHECK(normal[3 * i] == SB_INVALID_NORMAL);
  CHECK(normal[3 * 0 + 2] == Approx(-1.0f));
}

TEST_CASE("sbExp matches exp over the range the kernels use", "[pipeline][kernels]") {
  for (float x = -60.0f; x <= 10.0f; x += 0.37f) CHECK(sbExp(x) == Approx(std::exp(double(x))).epsilon(5e-7));
}

TEST_CASE("the CPU backend's row-wise bilateralFilter is bit-identical to the per-pixel kernel", "[pipeline][kernels]") {
  sb::Intrinsics k;
  k.width = 37;
  k.height = 23;
  k.fx = k.fy = 30.0f;
  k.cx = 18.0f;
  k.cy = 11.0f;
  sb::DepthRaw raw(k.width, k.height);
  uint32_t seed = 12345;
  for (auto& v : raw.pixels()) {
    seed = seed * 1664525u + 1013904223u;
    v = (seed >> 28) == 0 ? 0 : static_cast<uint16_t>(800 + (seed >> 20) % 400);  // holes and 0.8-1.2 m
  }
  sb::PipelineConfig config;
  config.volumeResolution = 8;
  sb::ThreadPool pool(2);
  sb::CpuBackend backend(config, k, pool);
  sb::StageTimes times;
  backend.preprocess(raw, 1e-3f, 1, times);
  const auto g = gaussian(config.bilateralRadius, config.bilateralSpatialSigma);
  const std::vector<float>& metres = backend.rawMetres();
  std::vector<float> expected(metres.size());
  for (int y = 0; y < k.height; ++y)
    for (int x = 0; x < k.width; ++x)
      bilateralFilter(expected.data(), metres.data(), k.width, k.height, g.data(), config.bilateralRadius,
                      config.bilateralRangeSigma, x, y);
  const std::vector<float>& filtered = backend.levelDepth(0);
  for (size_t i = 0; i < expected.size(); ++i) CHECK(filtered[i] == expected[i]);
}
