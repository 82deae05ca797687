#pragma once
// The compute backend named by the config (architecture.md D3): `backend: cpu | opencl | auto`, the OpenCL
// device by `opencl_platform` / `opencl_device`, half storage by `opencl_half_storage`.

#include <memory>

#include "core/intrinsics.h"
#include "core/thread_pool.h"
#include "pipeline/backend.h"
#include "pipeline/config.h"

namespace sb {

// cpu: the CPU backend on `pool` (borrowed; must outlive the backend). opencl: the selected OpenCL device;
// throws sb::Error saying what is missing (no platform, no matching device, build failure) and what to do.
// auto: OpenCL on a GPU or accelerator (or on the device the selectors name); otherwise, or when the OpenCL
// backend cannot start, the CPU backend after one warning (spdlog) that says why.
std::unique_ptr<ComputeBackend> makeBackend(const PipelineConfig& config, const Intrinsics& fullSize, ThreadPool& pool);

}  // namespace sb
