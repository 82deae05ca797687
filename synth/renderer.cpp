#include "synth/renderer.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/thread_pool.h"
#include "synth/intersect.h"

namespace sb::synth {

namespace {

constexpr int kTilePx = 16;          // tile side for primitive binning, pixels
constexpr double kNearClipM = 1e-3;  // camera-plane clip for projecting bounding boxes, metres
constexpr float kMinHitT = 1e-4f;    // ignore hits nearer than this depth, metres
// Corner index pairs of the 12 box edges (corners numbered by bits x=1, y=2, z=4).
constexpr int kEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                               {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

}  // namespace

struct Renderer::FrameSetup {
  // Per primitive: camera ray direction -> local direction, camera origin in local coordinates.
  std::vector<Eigen::Matrix3f> cameraToLocal;
  std::vector<Eigen::Vector3f> originLocal;
  std::vector<int> unbounded;               // primitives every pixel tests
  std::vector<std::vector<int>> tileLists;  // bounded primitives per tile
  int tilesX = 0, tilesY = 0;
};

Renderer::Renderer(const Scene& scene, const Intrinsics& intrinsics) : scene_(scene), intrinsics_(intrinsics) {
  if (intrinsics.width <= 0 || intrinsics.height <= 0 || intrinsics.fx <= 0.f || intrinsics.fy <= 0.f) {
    throw Error("synth renderer: invalid intrinsics " + std::to_string(intrinsics.width) + "x" +
                std::to_string(intrinsics.height) + " fx " + std::to_string(intrinsics.fx) + " fy " +
                std::to_string(intrinsics.fy) + "; width, height, fx and fy must be positive");
  }
}

void Renderer::renderIdeal(const Eigen::Isometry3d& T_camera_to_world, IdealFrame& out, bool parallel) const {
  const Intrinsics& k = intrinsics_;
  FrameSetup s;
  s.tilesX = (k.width + kTilePx - 1) / kTilePx;
  s.tilesY = (k.height + kTilePx - 1) / kTilePx;
  s.tileLists.resize(static_cast<size_t>(s.tilesX) * s.tilesY);
  const Eigen::Matrix3d R_wc = T_camera_to_world.linear();
  const Eigen::Vector3d t_wc = T_camera_to_world.translation();
  const Eigen::Isometry3d T_world_to_camera = T_camera_to_world.inverse();

  const size_t n = scene_.primitives.size();
  s.cameraToLocal.resize(n);
  s.originLocal.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const Primitive& p = scene_.primitives[i];
    const Eigen::Matrix3d Rt = p.rotation.cast<double>().transpose();
    s.cameraToLocal[i] = (Rt * R_wc).cast<float>();
    s.originLocal[i] = (Rt * (t_wc - p.center.cast<double>())).cast<float>();
    if (!p.bounded()) {
      s.unbounded.push_back(static_cast<int>(i));
      continue;
    }
    // Screen rectangle of the bounding box clipped to z >= kNearClipM: in-front corners plus edge crossings.
    std::vector<Eigen::Vector3d> cam;
    for (const Eigen::Vector3f& c : p.corners()) cam.push_back(T_world_to_camera * c.cast<double>());
    double uMin = 1e30, uMax = -1e30, vMin = 1e30, vMax = -1e30;
    bool any = false;
    auto addPoint = [&](const Eigen::Vector3d& q) {
      const double u = k.fx * q.x() / q.z() + k.cx, v = k.fy * q.y() / q.z() + k.cy;
      uMin = std::min(uMin, u), uMax = std::max(uMax, u);
      vMin = std::min(vMin, v), vMax = std::max(vMax, v);
      any = true;
    };
    for (const Eigen::Vector3d& q : cam) {
      if (q.z() >= kNearClipM) addPoint(q);
    }
    for (const auto& e : kEdges) {
      const Eigen::Vector3d& a = cam[e[0]];
      const Eigen::Vector3d& b = cam[e[1]];
      if ((a.z() < kNearClipM) != (b.z() < kNearClipM)) {
        const double f = (kNearClipM - a.z()) / (b.z() - a.z());
        addPoint(a + f * (b - a));
      }
    }
    if (!any) continue;
    // Pixel (x, y) covers [x - 0.5, x + 0.5]; rays go through pixel centres.
    const int x0 = static_cast<int>(std::clamp(std::floor(uMin), 0.0, k.width - 1.0));
    const int x1 = static_cast<int>(std::clamp(std::ceil(uMax), 0.0, k.width - 1.0));
    const int y0 = static_cast<int>(std::clamp(std::floor(vMin), 0.0, k.height - 1.0));
    const int y1 = static_cast<int>(std::clamp(std::ceil(vMax), 0.0, k.height - 1.0));
    if (uMax < 0.0 || vMax < 0.0 || uMin > k.width - 1.0 || vMin > k.height - 1.0) continue;
    for (int ty = y0 / kTilePx; ty <= y1 / kTilePx; ++ty) {
      for (int tx = x0 / kTilePx; tx <= x1 / kTilePx; ++tx) {
        s.tileLists[static_cast<size_t>(ty) * s.tilesX + tx].push_back(static_cast<int>(i));
      }
    }
  }

  out.depthM.resize(k.width, k.height);
  out.cosIncidence.resize(k.width, k.height);
  if (parallel) {
    ThreadPool::global().parallelFor(0, k.height, kTilePx,
                                     [&](int, int begin, int end) { renderRows(s, begin, end, out); });
  } else {
    renderRows(s, 0, k.height, out);
  }
}

void Renderer::renderRows(const FrameSetup& s, int rowBegin, int rowEnd, IdealFrame& out) const {
  const Intrinsics& k = intrinsics_;
  const auto& prims = scene_.primitives;
  for (int y = rowBegin; y < rowEnd; ++y) {
    const std::vector<int>* tileRow = &s.tileLists[static_cast<size_t>(y / kTilePx) * s.tilesX];
    for (int x = 0; x < k.width; ++x) {
      const Eigen::Vector3f dir((x - k.cx) / k.fx, (y - k.cy) / k.fy, 1.f);
      float best = kNoHit;
      int bestIndex = -1;
      auto test = [&](int i) {
        const Eigen::Vector3f d = s.cameraToLocal[i] * dir;
        const float t = intersectLocal(prims[i].shape, s.originLocal[i], d, prims[i].halfExtents, kMinHitT);
        if (t < best) best = t, bestIndex = i;
      };
      for (int i : s.unbounded) test(i);
      for (int i : tileRow[x / kTilePx]) test(i);
      if (bestIndex < 0) {
        out.depthM(x, y) = 0.f;
        out.cosIncidence(x, y) = 0.f;
        continue;
      }
      const Primitive& p = prims[bestIndex];
      const Eigen::Vector3f d = s.cameraToLocal[bestIndex] * dir;
      const Eigen::Vector3f n = normalLocal(p.shape, s.originLocal[bestIndex] + best * d, p.halfExtents);
      out.depthM(x, y) = best;
      out.cosIncidence(x, y) = std::abs(n.dot(d)) / d.norm();
    }
  }
}

void Renderer::render(const Eigen::Isometry3d& T_camera_to_world, const SensorModel& model, uint64_t seed,
                      DepthMeters& out, bool parallel) const {
  IdealFrame ideal;
  renderIdeal(T_camera_to_world, ideal, parallel);
  out.resize(intrinsics_.width, intrinsics_.height);
  if (parallel) {
    ThreadPool::global().parallelFor(0, intrinsics_.height, kTilePx, [&](int, int begin, int end) {
      applySensorModel(ideal, model, intrinsics_.fx, seed, begin, end, out);
    });
  } else {
    applySensorModel(ideal, model, intrinsics_.fx, seed, 0, intrinsics_.height, out);
  }
}

}  // namespace sb::synth
