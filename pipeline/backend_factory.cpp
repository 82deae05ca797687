#include "pipeline/backend_factory.h"

#include <spdlog/spdlog.h>

#include "core/error.h"
#include "pipeline/cpu/cpu_backend.h"
#ifdef SB_HAVE_OPENCL
#include "pipeline/opencl/device.h"
#include "pipeline/opencl/opencl_backend.h"
#endif

namespace sb {

namespace {

constexpr const char* kInstallHint =
    "install an OpenCL driver (e.g. pocl-opencl-icd for the CPU, the GPU vendor's ICD) or set 'backend' to cpu";

std::unique_ptr<ComputeBackend> cpuFallback(const PipelineConfig& config, const Intrinsics& fullSize, ThreadPool& pool,
                                            const std::string& why) {
  spdlog::warn("backend auto: {}; using the cpu backend{}", why,
               config.openclHalfStorage ? " (float storage: opencl_half_storage is ignored)" : "");
  PipelineConfig cpu = config;
  cpu.openclHalfStorage = false;
  return std::make_unique<CpuBackend>(cpu, fullSize, pool);
}

#ifdef SB_HAVE_OPENCL
std::unique_ptr<ComputeBackend> openclBackend(const PipelineConfig& config, const Intrinsics& fullSize,
                                              const opencl::DeviceInfo& device) {
  auto backend = std::make_unique<OpenClBackend>(config, fullSize, device);
  spdlog::info("compute backend: opencl on '{}' ({}, {}){}", device.deviceName, device.platformName, device.version,
               config.openclHalfStorage ? ", half storage" : "");
  return backend;
}
#endif

}  // namespace

std::unique_ptr<ComputeBackend> makeBackend(const PipelineConfig& config, const Intrinsics& fullSize, ThreadPool& pool) {
  validateConfig(config);
  if (config.backend == BackendKind::cpu) return std::make_unique<CpuBackend>(config, fullSize, pool);
  const bool automatic = config.backend == BackendKind::automatic;
#ifndef SB_HAVE_OPENCL
  if (automatic) return cpuFallback(config, fullSize, pool, "this build has no OpenCL support");
  throw Error("backend opencl: this build has no OpenCL support (rebuild with the OpenCL headers and ICD loader, "
              "package ocl-icd-opencl-dev) or set 'backend' to cpu");
#else
  std::vector<opencl::DeviceInfo> devices;
  try {
    devices = opencl::listDevices();
  } catch (const Error& e) {
    if (automatic) return cpuFallback(config, fullSize, pool, std::string("listing OpenCL devices failed: ") + e.what());
    throw;
  }
  if (devices.empty()) {
    if (automatic) return cpuFallback(config, fullSize, pool, "no OpenCL platform found");
    throw Error(std::string("backend opencl: no OpenCL platform found; ") + kInstallHint);
  }
  const bool named = !config.openclPlatform.empty() || !config.openclDevice.empty();
  // Selectors that match nothing are an error in every mode: the user asked for that device.
  const opencl::DeviceInfo device = opencl::selectDevice(devices, config.openclPlatform, config.openclDevice);
  if (automatic && !named && !device.gpu)
    return cpuFallback(config, fullSize, pool,
                       "no OpenCL GPU found (only CPU devices such as PoCL: set 'backend' to "
                       "opencl to use them)");
  try {
    return openclBackend(config, fullSize, device);
  } catch (const Error& e) {
    if (automatic) return cpuFallback(config, fullSize, pool, std::string("the OpenCL backend failed: ") + e.what());
    throw Error("backend opencl on '" + device.deviceName + "': " + e.what());
  }
#endif
}

}  // namespace sb
