#include "pipeline/opencl/opencl_backend.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "kernels/raycast.h"
#include "kernels/track.h"
#include "pipeline/kernel_args.h"
#include "pipeline/opencl/device_state.h"

namespace sb {

using opencl::Launcher;
using Clock = Launcher::Clock;

namespace {

const Launcher::Size3 kImageGroup{16, 8, 1};   // 128 work-items: <= 256 and a multiple of 4 (Mali-T6xx)
const Launcher::Size3 kVolumeGroup{16, 4, 2};  // 128 work-items, x fastest (neighbouring voxels)
const Launcher::Size3 kLinearGroup{128, 1, 1};
constexpr int kWorkBlockShift = 3;  // StageWork::integrateBlocks counts blocks of 8^3 voxels

Launcher::Size3 imageSize(const Intrinsics& k) { return {size_t(k.width), size_t(k.height), 1}; }


}  // namespace

OpenClBackend::OpenClBackend(const PipelineConfig& config, const Intrinsics& fullSize, const opencl::DeviceInfo& device)
    : s_(std::make_unique<State>(config, fullSize, device)) {
  if (config.openclHalfStorage) setHalfPrecision(true);
}

OpenClBackend::~OpenClBackend() = default;

const opencl::DeviceInfo& OpenClBackend::device() const { return s_->device; }
bool OpenClBackend::halfPrecision() const { return s_->half; }
const Intrinsics& OpenClBackend::levelIntrinsics(int level) const { return s_->levels.at(level).k; }
const Intrinsics& OpenClBackend::referenceIntrinsics() const { return s_->referenceK; }

void OpenClBackend::preprocess(const DepthRaw& raw, float metresPerUnit, int csr, StageTimes& times) {
  State& s = *s_;
  const auto start = Clock::now();
  s.upload(raw);
  s.computeK = s.full.scaled(csr);
  for (int l = 0; l < kPyramidLevels; ++l) s.levels[l].k = s.full.scaled(csr << l);
  s.hasFrame = true;
  s.hasTrack = false;
  const opencl::Kernels& k = s.kernels();
  Launcher& q = s.launcher;
  const PipelineConfig& c = s.config;
  const int w = s.computeK.width, h = s.computeK.height;
  q.run(Stage::mm2meters, k.mm2meters, imageSize(s.computeK), kImageGroup, s.depth, w, h, s.raw, raw.width(), csr,
        metresPerUnit);
  s.useBilateralTaps();
  q.run(Stage::bilateralFilter, k.bilateralFilter, imageSize(s.computeK), kImageGroup, s.levels[0].depth, s.depth, w,
        h, s.gaussian, s.tapsRadius, c.bilateralRangeSigma);
  for (int l = 1; l < kPyramidLevels; ++l) {
    const State::Level& fine = s.levels[l - 1];
    const State::Level& coarse = s.levels[l];
    q.run(Stage::halfSampleRobust, k.halfSampleRobust, imageSize(coarse.k), kImageGroup, coarse.depth, coarse.k.width,
          coarse.k.height, fine.depth, fine.k.width, fine.k.height, c.halfSampleMaxDifference);
  }
  for (const State::Level& level : s.levels)
    q.run(Stage::depth2vertex, k.depth2vertex, imageSize(level.k), kImageGroup, level.vertex, level.depth,
          level.k.width, level.k.height, toCamera(level.k));
  for (const State::Level& level : s.levels)
    q.run(Stage::vertex2normal, k.vertex2normal, imageSize(level.k), kImageGroup, level.normal, level.vertex,
          level.k.width, level.k.height);
  q.finish(times, start);
}

TrackSums OpenClBackend::track(int level, const Eigen::Isometry3f& cameraToWorld,
                               const Eigen::Isometry3f& referencePose, StageTimes& times) {
  State& s = *s_;
  const auto start = Clock::now();
  const State::Level& in = s.levels.at(level);
  const Eigen::Matrix<float, 3, 4> projection =
      cameraMatrix(s.referenceK) * referencePose.inverse().matrix().topRows<3>();
  const opencl::Kernels& k = s.kernels();
  Launcher& q = s.launcher;
  s.trackCameraToWorld = toMat34(cameraToWorld.matrix());
  s.trackWorldToRefPixel = toMat34(projection);
  q.run(Stage::track, k.track, imageSize(in.k), kImageGroup, s.trackOut, in.vertex, in.normal, in.k.width,
        in.k.height, s.referenceVertex, s.referenceNormal, s.referenceK.width, s.referenceK.height,
        s.trackCameraToWorld, s.trackWorldToRefPixel, s.config.icpDistanceThreshold, s.config.icpNormalThreshold);
  s.trackK = in.k;
  s.trackLevel = level;
  s.hasTrack = true;
  const TrackSums sums = s.reduceRows(s.trackOut, in.k.width * in.k.height);
  q.finish(times, start);
  return sums;
}

TrackSums OpenClBackend::blockSums(int block, StageTimes& times) {
  State& s = *s_;
  if (!s.hasTrack) throw Error("OpenClBackend::blockSums called without a track since the last preprocess or raycast");
  if (block < 1) throw Error("OpenClBackend::blockSums: block " + std::to_string(block) + " is not positive");
  const auto start = Clock::now();
  const int blocksX = (s.trackK.width + block - 1) / block, blocksY = (s.trackK.height + block - 1) / block;
  s.launcher.run(Stage::reduce, s.kernels().block, {size_t(blocksX), size_t(blocksY), 1}, kImageGroup, s.blockOut,
                 s.trackOut, s.trackK.width, s.trackK.height, block);
  const TrackSums sums = s.reduceRows(s.blockOut, blocksX * blocksY);
  s.launcher.finish(times, start);
  return sums;
}

void OpenClBackend::integrate(const Eigen::Isometry3f& cameraToWorld, StageTimes& times) {
  State& s = *s_;
  if (!s.hasFrame) throw Error("OpenClBackend::integrate called before any preprocess");
  const auto start = Clock::now();
  const opencl::Kernels& k = s.kernels();
  const PipelineConfig& c = s.config;
  const size_t r = size_t(c.volumeResolution);
  const Eigen::Isometry3f cameraToVolume = s.placement.toVolumeFrame(cameraToWorld);
  const SbMat34 worldToCamera = toMat34(cameraToVolume.inverse().matrix());
  // Every voxel, free space carved (KinectFusion's integration; no culling on the device).
  const int w = s.computeK.width, h = s.computeK.height;
  s.launcher.run(Stage::integrate, k.integrate, {r, r, r}, kVolumeGroup, s.volume, c.volumeResolution,
                 s.placement.offset(), c.volumeSize, worldToCamera, s.depth, w, h, toCamera(s.computeK), c.mu,
                 c.maxWeight);
  times.work.carvingIntegrations += 1;
  times.work.integrateBlocks += static_cast<long long>(r * r * r) >> (3 * kWorkBlockShift);
  // As the CPU backend, but only when the raycast uses it.
  if (c.emptySpaceSkipping) s.updateSkipping(Stage::integrate);
  s.volumeOnHost = false;
  s.launcher.finish(times, start);
}

void OpenClBackend::raycast(const Eigen::Isometry3f& cameraToWorld, int csr, StageTimes& times) {
  State& s = *s_;
  const auto start = Clock::now();
  s.referenceK = s.full.scaled(csr);
  s.hasReference = true;
  s.hasTrack = false;
  const PipelineConfig& c = s.config;
  const opencl::Buffer* blockDistance = c.emptySpaceSkipping ? &s.blockDistance : nullptr;
  const SbMat34 cameraToVolume = toMat34(s.placement.toVolumeFrame(cameraToWorld).matrix());
  const opencl::Buffer* bounds = nullptr;  // the ray bounds come from the same grid (pipeline/ray_bounds.h)
  if (c.emptySpaceSkipping) {
    s.rayBounds.compute(s.blockDistanceHost.data(), SB_SKIP_SHIFT, c.volumeResolution, c.volumeSize, cameraToVolume,
                        toCamera(s.referenceK), s.referenceK.width, s.referenceK.height);
    opencl::check(clEnqueueWriteBuffer(s.launcher.queue(), s.rayBoundsBuffer.get(), CL_TRUE, 0,
                                       s.rayBounds.bounds().size() * sizeof(float), s.rayBounds.bounds().data(), 0,
                                       nullptr, nullptr),
                  "writing the raycast's ray bounds");
    bounds = &s.rayBoundsBuffer;
  }
  s.launcher.run(Stage::raycast, s.kernels().raycast, imageSize(s.referenceK), kImageGroup, s.referenceVertex,
                 s.referenceNormal, s.referenceK.width, s.referenceK.height, s.volume, c.volumeResolution,
                 s.placement.offset(), c.volumeSize, blockDistance, bounds, s.rayBounds.columns(),
                 cameraToVolume, toCamera(s.referenceK), c.nearPlane,
                 c.farPlane, c.raycastLargeStep * c.mu, c.raycastSmallStep * c.voxelSize(), c.raycastSmallStepBelow);
  if (s.placement.moved()) {  // the maps in the world frame (a volume that never moved skips this)
    cl_float4 corner{};
    const Eigen::Vector3f c3 = s.placement.cornerMetres();
    for (int a = 0; a < 3; ++a) corner.s[a] = c3[a];
    s.launcher.run(Stage::raycast, s.kernels().offsetVertex, imageSize(s.referenceK), kImageGroup, s.referenceVertex,
                   s.referenceNormal, s.referenceK.width, s.referenceK.height, corner);
  }
  s.launcher.finish(times, start);
}

Image<uint8_t> OpenClBackend::render(const Eigen::Vector3f& lightPosition, StageTimes& times) {
  State& s = *s_;
  const auto start = Clock::now();
  const int w = s.referenceK.width, h = s.referenceK.height;
  cl_float4 light{};
  light.s[0] = lightPosition.x();
  light.s[1] = lightPosition.y();
  light.s[2] = lightPosition.z();
  s.launcher.run(Stage::render, s.kernels().render, imageSize(s.referenceK), kImageGroup, s.image, s.referenceVertex,
                 s.referenceNormal, w, h, light, s.config.renderAmbient);
  Image<uint8_t> image(w, h);
  s.read(s.image, image.data(), image.size());
  s.launcher.finish(times, start);
  return image;
}

const int16_t* OpenClBackend::volumeData() {
  State& s = *s_;
  if (!s.volumeOnHost) {
    s.read(s.volume, s.volumeHost.data(), s.volumeHost.size() * sizeof(int16_t));
    s.volumeOnHost = true;
  }
  return s.volumeHost.data();
}

void OpenClBackend::readVolumeBox(const std::array<int, 3>& first, const std::array<int, 3>& extent,
                                  int16_t* out) {
  State& s = *s_;
  constexpr size_t kVoxelBytes = 2 * sizeof(int16_t);  // (tsdf, weight)
  const size_t res = size_t(s.config.volumeResolution);
  const std::vector<BoxPiece> pieces =
      boxPieces(first, extent, s.placement.offset(), s.config.volumeResolution);
  for (size_t i = 0; i < pieces.size(); ++i) {
    const BoxPiece& p = pieces[i];
    const size_t bufferOrigin[3] = {size_t(p.physical[0]) * kVoxelBytes, size_t(p.physical[1]),
                                    size_t(p.physical[2])};
    const size_t hostOrigin[3] = {size_t(p.inBox[0]) * kVoxelBytes, size_t(p.inBox[1]), size_t(p.inBox[2])};
    const size_t region[3] = {size_t(p.extent[0]) * kVoxelBytes, size_t(p.extent[1]), size_t(p.extent[2])};
    const size_t hostRow = size_t(extent[0]) * kVoxelBytes;
    // The queue is in order: the reads follow the kernels queued before; the last one waits for all.
    opencl::check(clEnqueueReadBufferRect(s.launcher.queue(), s.volume.get(),
                                          i + 1 == pieces.size() ? CL_TRUE : CL_FALSE, bufferOrigin,
                                          hostOrigin, region, res * kVoxelBytes, res * res * kVoxelBytes,
                                          hostRow, hostRow * size_t(extent[1]), out, 0, nullptr, nullptr),
                  "clEnqueueReadBufferRect (a box of the volume)");
  }
}

void OpenClBackend::writeVolumeBox(const std::array<int, 3>& first, const std::array<int, 3>& extent,
                                   const int16_t* in) {
  State& s = *s_;
  constexpr size_t kVoxelBytes = 2 * sizeof(int16_t);  // (tsdf, weight)
  const size_t res = size_t(s.config.volumeResolution);
  const std::vector<BoxPiece> pieces = boxPieces(first, extent, s.placement.offset(), s.config.volumeResolution);
  for (const BoxPiece& p : pieces) {
    const size_t bufferOrigin[3] = {size_t(p.physical[0]) * kVoxelBytes, size_t(p.physical[1]),
                                    size_t(p.physical[2])};
    const size_t hostOrigin[3] = {size_t(p.inBox[0]) * kVoxelBytes, size_t(p.inBox[1]), size_t(p.inBox[2])};
    const size_t region[3] = {size_t(p.extent[0]) * kVoxelBytes, size_t(p.extent[1]), size_t(p.extent[2])};
    const size_t hostRow = size_t(extent[0]) * kVoxelBytes;
    // Blocking: `in` is the caller's and may go once this returns.
    opencl::check(clEnqueueWriteBufferRect(s.launcher.queue(), s.volume.get(), CL_TRUE, bufferOrigin, hostOrigin,
                                           region, res * kVoxelBytes, res * res * kVoxelBytes, hostRow,
                                           hostRow * size_t(extent[1]), in, 0, nullptr, nullptr),
                  "clEnqueueWriteBufferRect (a box of the volume)");
  }
  s.volumeOnHost = false;
  s.updateSkipping(Stage::integrate);  // from the volume as it is now
  StageTimes ignored;
  s.launcher.finish(ignored, Clock::now());
}

void OpenClBackend::moveVolume(const Eigen::Vector3i& cornerVoxels) {
  State& s = *s_;
  const int res = s.config.volumeResolution;
  bool cleared = false;
  for (const VolumePlacement::Clear& c : s.placement.moveTo(cornerVoxels)) {
    s.launcher.run(Stage::integrate, s.kernels().clearSlab, {size_t(c.count), size_t(res), size_t(res)},
                   kVolumeGroup, s.volume, res, c.axis, c.first, c.count);
    cleared = true;
  }
  if (!cleared) return;
  s.volumeOnHost = false;
  // The skipping grid from the volume as it is now (blocks are logical: the offset moved them).
  s.updateSkipping(Stage::integrate);
  StageTimes ignored;
  s.launcher.finish(ignored, Clock::now());
}

void OpenClBackend::setHalfPrecision(bool enabled) {
  State& s = *s_;
  if (enabled == s.half) return;
  s.variant(enabled);  // build it first: a failed build leaves the float state untouched
  for (auto& [buffer, count] : s.maps()) s.convert(*buffer, count, enabled);
  s.half = enabled;
}

std::vector<float> OpenClBackend::levelDepth(int level) {
  return s_->readMap(s_->levels.at(level).depth, s_->pixels(s_->levels.at(level).k, s_->hasFrame));
}
std::vector<float> OpenClBackend::levelVertices(int level) {
  return s_->readMap(s_->levels.at(level).vertex, 3 * s_->pixels(s_->levels.at(level).k, s_->hasFrame));
}
std::vector<float> OpenClBackend::levelNormals(int level) {
  return s_->readMap(s_->levels.at(level).normal, 3 * s_->pixels(s_->levels.at(level).k, s_->hasFrame));
}
std::vector<float> OpenClBackend::rawMetres() { return s_->readMap(s_->depth, s_->pixels(s_->computeK, s_->hasFrame)); }
std::vector<float> OpenClBackend::referenceVertices() {
  return s_->readMap(s_->referenceVertex, 3 * s_->pixels(s_->referenceK, s_->hasReference));
}
std::vector<float> OpenClBackend::referenceNormals() {
  return s_->readMap(s_->referenceNormal, 3 * s_->pixels(s_->referenceK, s_->hasReference));
}

}  // namespace sb
