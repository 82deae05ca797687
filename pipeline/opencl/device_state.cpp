#include "pipeline/opencl/device_state.h"

#include "pipeline/bilateral_taps.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/error.h"
#include "kernels/raycast.h"
#include "kernels/track.h"
#include "pipeline/block_distance.h"
#include "pipeline/opencl/kernel_sources.h"

namespace sb {

namespace opencl {

Kernels::Kernels(const Launcher& launcher, const DeviceInfo& device, bool halfStorage, const std::string& sourceDir) {
  std::string options = "-cl-std=CL1.2 -DSB_REDUCE_GROUP=" + std::to_string(kReduceGroup);
  if (halfStorage) options += " -DSB_MAP_HALF";
  if (device.fp64) options += " -DSB_HAVE_FP64";
  std::string source;
  try {
    source = assembleProgram(programEntries(), sourceDir.empty() ? embeddedLoader() : directoryLoader(sourceDir));
  } catch (const Error& e) {
    if (sourceDir.empty()) throw;
    throw Error(std::string(e.what()) + " (opencl_source_dir '" + sourceDir + "')");
  }
  program = buildProgram(launcher.context(), launcher.device(), source, options);
  const cl_program p = program.get();
  mm2meters = createKernel(p, "mm2metersKernel");
  bilateralFilter = createKernel(p, "bilateralFilterKernel");
  halfSampleRobust = createKernel(p, "halfSampleRobustKernel");
  depth2vertex = createKernel(p, "depth2vertexKernel");
  vertex2normal = createKernel(p, "vertex2normalKernel");
  track = createKernel(p, "trackKernel");
  block = createKernel(p, "blockKernel");
  reduce = createKernel(p, "reduceKernel");
  reduceFinal = createKernel(p, "reduceFinalKernel");
  initVolume = createKernel(p, "initVolumeKernel");
  integrate = createKernel(p, "integrateKernel");
  clearSlab = createKernel(p, "clearSlabKernel");
  surfaceMask = createKernel(p, "surfaceMaskKernel");
  raycast = createKernel(p, "raycastKernel");
  offsetVertex = createKernel(p, "offsetVertexKernel");
  render = createKernel(p, "renderKernel");
  halfToFloat = createKernel(p, "halfToFloatKernel");
  floatToHalf = createKernel(p, "floatToHalfKernel");
}

}  // namespace opencl

using opencl::createBuffer;
using opencl::Launcher;

OpenClBackend::State::State(const PipelineConfig& c, const Intrinsics& fullSize, const opencl::DeviceInfo& d)
    : config(c),
      full(fullSize),
      device(d),
      launcher(d),
      computeK(fullSize),
      referenceK(fullSize),
      placement(c.volumeResolution, c.voxelSize()) {
  validateConfig(config);
  const cl_context ctx = launcher.context();
  const size_t n = size_t(full.width) * full.height;
  const size_t f = sizeof(float);
  raw = createBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_ALLOC_HOST_PTR, n * sizeof(uint16_t), "raw depth");
  // Sized for the full image's taps, the widest (pipeline/bilateral_taps.h); written per compute size.
  gaussian = createBuffer(ctx, CL_MEM_READ_ONLY, (2 * size_t(config.bilateralRadius) + 1) * f, "bilateral weights");
  depth = createBuffer(ctx, CL_MEM_READ_WRITE, n * f, "depth");
  for (int l = 0; l < kPyramidLevels; ++l) {
    const Intrinsics k = full.scaled(1 << l);
    const size_t ln = size_t(k.width) * k.height;
    levels[l].k = k;
    levels[l].depth = createBuffer(ctx, CL_MEM_READ_WRITE, ln * f, "pyramid depth");
    levels[l].vertex = createBuffer(ctx, CL_MEM_READ_WRITE, 3 * ln * f, "pyramid vertices");
    levels[l].normal = createBuffer(ctx, CL_MEM_READ_WRITE, 3 * ln * f, "pyramid normals");
  }
  trackOut = createBuffer(ctx, CL_MEM_READ_WRITE, SB_TRACK_STRIDE * n * f, "track output");
  blockOut = createBuffer(ctx, CL_MEM_READ_WRITE, SB_TRACK_STRIDE * n * f, "block rows");
  partial = createBuffer(ctx, CL_MEM_READ_WRITE, opencl::kMaxReduceGroups * SB_REDUCE_SIZE * f, "reduce partials");
  sums = createBuffer(ctx, CL_MEM_READ_WRITE, SB_REDUCE_SIZE * sizeof(double), "reduce sums");
  referenceVertex = createBuffer(ctx, CL_MEM_READ_WRITE, 3 * n * f, "raycast vertices");
  referenceNormal = createBuffer(ctx, CL_MEM_READ_WRITE, 3 * n * f, "raycast normals");
  const size_t res = size_t(config.volumeResolution);
  const size_t voxels = res * res * res;
  volume = createBuffer(ctx, CL_MEM_READ_WRITE, 2 * voxels * sizeof(int16_t), "TSDF volume");
  const size_t blocks = res >> SB_SKIP_SHIFT;
  blockMasks = createBuffer(ctx, CL_MEM_READ_WRITE, blocks * blocks * blocks, "skipping block masks");
  blockDistance = createBuffer(ctx, CL_MEM_READ_ONLY, blocks * blocks * blocks, "skipping block distances");
  blockMasksHost.resize(blocks * blocks * blocks);
  const size_t tiles = size_t((full.width + RayBounds::kTile - 1) / RayBounds::kTile) *
                       size_t((full.height + RayBounds::kTile - 1) / RayBounds::kTile);
  rayBoundsBuffer = createBuffer(ctx, CL_MEM_READ_ONLY, 2 * tiles * f, "raycast ray bounds");
  image = createBuffer(ctx, CL_MEM_WRITE_ONLY, n, "render image");
  scratch = createBuffer(ctx, CL_MEM_READ_WRITE, 3 * n * f, "conversion scratch");
  volumeHost.resize(2 * voxels);

  const opencl::Kernels& k = variant(false);
  if (launcher.maxGroupSize(k.reduce.get()) < opencl::kReduceGroup)
    throw Error("OpenCL device '" + device.deviceName + "' runs reduceKernel with fewer than " +
                std::to_string(opencl::kReduceGroup) + " work-items per group; use another device or the cpu backend");
  StageTimes ignored;
  launcher.run(Stage::integrate, k.initVolume, {voxels, 1, 1}, {128, 1, 1}, volume, static_cast<int>(voxels));
  updateSkipping(Stage::integrate);
  launcher.finish(ignored, Launcher::Clock::now());
}

void OpenClBackend::State::updateSkipping(Stage stage) {
  const int res = config.volumeResolution, blocks = res >> SB_SKIP_SHIFT;
  const size_t b = size_t(blocks);
  launcher.run(stage, kernels().surfaceMask, {b, b, b}, {16, 4, 2}, blockMasks, volume, res, placement.offset(), blocks,
               static_cast<int>(surfaceTsdfBelow(config.raycastSmallStepBelow)));
  read(blockMasks, blockMasksHost.data(), blockMasksHost.size());
  computeBlockDistance(blockMasksHost, blocks, blockDistanceHost, skipPool);
  opencl::check(clEnqueueWriteBuffer(launcher.queue(), blockDistance.get(), CL_TRUE, 0, blockDistanceHost.size(),
                                     blockDistanceHost.data(), 0, nullptr, nullptr),
                "writing the skipping block distances");
}

const opencl::Kernels& OpenClBackend::State::variant(bool halfStorage) {
  std::unique_ptr<opencl::Kernels>& v = variants[halfStorage ? 1 : 0];
  if (!v) v = std::make_unique<opencl::Kernels>(launcher, device, halfStorage, config.openclSourceDir);
  return *v;
}

void OpenClBackend::State::upload(const DepthRaw& frame) {
  if (frame.width() != full.width || frame.height() != full.height)
    throw Error("OpenClBackend: frame is " + std::to_string(frame.width()) + "x" + std::to_string(frame.height()) +
                " but the backend was made for " + std::to_string(full.width) + "x" + std::to_string(full.height));
  const size_t bytes = frame.size() * sizeof(uint16_t);
  cl_int code = CL_SUCCESS;
  void* mapped = clEnqueueMapBuffer(launcher.queue(), raw.get(), CL_TRUE, CL_MAP_WRITE_INVALIDATE_REGION, 0, bytes, 0,
                                    nullptr, nullptr, &code);
  opencl::check(code, "mapping the raw depth buffer");
  std::memcpy(mapped, frame.data(), bytes);
  opencl::check(clEnqueueUnmapMemObject(launcher.queue(), raw.get(), mapped, 0, nullptr, nullptr),
                "unmapping the raw depth buffer");
}

void OpenClBackend::State::read(const opencl::Buffer& buffer, void* out, size_t bytes) {
  if (bytes == 0) return;
  opencl::check(clEnqueueReadBuffer(launcher.queue(), buffer.get(), CL_TRUE, 0, bytes, out, 0, nullptr, nullptr),
                "clEnqueueReadBuffer");
}

TrackSums OpenClBackend::State::readSums() {
  TrackSums out{};
  if (device.fp64) {
    read(sums, out.data(), sizeof(double) * SB_REDUCE_SIZE);
  } else {
    std::array<float, SB_REDUCE_SIZE> values{};
    read(sums, values.data(), sizeof(float) * SB_REDUCE_SIZE);
    for (int i = 0; i < SB_REDUCE_SIZE; ++i) out[i] = values[i];
  }
  return out;
}

std::vector<float> OpenClBackend::State::readMap(const opencl::Buffer& buffer, size_t count) {
  std::vector<float> out(count);
  if (count == 0) return out;
  if (half) {
    StageTimes ignored;
    launcher.run(Stage::render, kernels().halfToFloat, {count, 1, 1}, {128, 1, 1}, scratch, buffer,
                 static_cast<int>(count));
    launcher.finish(ignored, Launcher::Clock::now());
    read(scratch, out.data(), count * sizeof(float));
  } else {
    read(buffer, out.data(), count * sizeof(float));
  }
  return out;
}

void OpenClBackend::State::convert(opencl::Buffer& buffer, size_t count, bool toHalf) {
  if (count == 0) return;
  const opencl::Kernels& k = variant(false);
  StageTimes ignored;
  launcher.run(Stage::render, toHalf ? k.floatToHalf : k.halfToFloat, {count, 1, 1}, {128, 1, 1}, scratch, buffer,
               static_cast<int>(count));
  opencl::check(clEnqueueCopyBuffer(launcher.queue(), scratch.get(), buffer.get(), 0, 0,
                                    count * (toHalf ? sizeof(cl_half) : sizeof(float)), 0, nullptr, nullptr),
                "clEnqueueCopyBuffer");
  launcher.finish(ignored, Launcher::Clock::now());
}

std::vector<std::pair<opencl::Buffer*, size_t>> OpenClBackend::State::maps() {
  std::vector<std::pair<opencl::Buffer*, size_t>> out;
  out.emplace_back(&depth, pixels(computeK, hasFrame));
  for (Level& level : levels) {
    const size_t n = pixels(level.k, hasFrame);
    out.emplace_back(&level.depth, n);
    out.emplace_back(&level.vertex, 3 * n);
    out.emplace_back(&level.normal, 3 * n);
  }
  out.emplace_back(&referenceVertex, 3 * pixels(referenceK, hasReference));
  out.emplace_back(&referenceNormal, 3 * pixels(referenceK, hasReference));
  return out;
}

TrackSums OpenClBackend::State::reduceRows(const opencl::Buffer& rowsBuffer, int rows) {
  const opencl::Kernels& k = kernels();
  const size_t perGroup = opencl::kReduceGroup * opencl::kPixelsPerReduceItem;
  const int groups = static_cast<int>(std::clamp<size_t>((rows + perGroup - 1) / perGroup, 1, opencl::kMaxReduceGroups));
  launcher.run(Stage::reduce, k.reduce, {groups * opencl::kReduceGroup, 1, 1}, {opencl::kReduceGroup, 1, 1}, partial,
               rowsBuffer, rows);
  launcher.run(Stage::reduce, k.reduceFinal, {SB_REDUCE_SIZE, 1, 1}, {SB_REDUCE_SIZE, 1, 1}, sums, partial, groups);
  return readSums();
}

void OpenClBackend::State::useBilateralTaps() {
  if (tapsWritten) return;
  const BilateralTaps taps = bilateralTaps(config);
  opencl::check(clEnqueueWriteBuffer(launcher.queue(), gaussian.get(), CL_TRUE, 0, taps.weights.size() * sizeof(float),
                                     taps.weights.data(), 0, nullptr, nullptr),
                "writing the bilateral weights");
  tapsRadius = taps.radius;
  tapsWritten = true;
}

}  // namespace sb
