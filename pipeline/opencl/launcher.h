#pragma once
// The OpenCL context and profiling queue of one device, and kernel launches on it: arguments, work-group sizes
// within the device's limits (Mali-T6xx: at most 256 work-items, multiples of 4), and per-stage timing from
// profiling events. Internal to pipeline/opencl/.

#include <array>
#include <chrono>
#include <map>
#include <type_traits>
#include <utility>
#include <vector>

#include "pipeline/opencl/cl_api.h"
#include "pipeline/opencl/device.h"
#include "pipeline/stages.h"

namespace sb::opencl {

class Launcher {
 public:
  using Clock = std::chrono::steady_clock;
  using Size3 = std::array<size_t, 3>;

  explicit Launcher(const DeviceInfo& device);

  cl_device_id device() const { return device_; }
  cl_context context() const { return context_.get(); }
  cl_command_queue queue() const { return queue_.get(); }

  // Enqueues `kernel` over `global` work-items (1 in unused dimensions), in groups of `local` or smaller where
  // the kernel allows fewer; the global size is rounded up (the wrappers check bounds). Its profiled time is
  // booked to `stage` at the next finish().
  template <typename... Args>
  void run(Stage stage, const Kernel& kernel, Size3 global, Size3 local, const Args&... args) {
    cl_uint index = 0;
    (setArg(kernel.get(), index++, args), ...);
    enqueue(stage, kernel.get(), global, local);
  }

  // CL_KERNEL_WORK_GROUP_SIZE: the most work-items per group the kernel can run with on this device.
  size_t maxGroupSize(cl_kernel kernel);

  // Waits for everything queued. Adds each kernel's profiled time to times.deviceMs[stage] and the host time
  // since `start` to times.ms, split over the stages of the finished kernels in proportion to their device times.
  void finish(StageTimes& times, Clock::time_point start);

 private:
  static void setArg(cl_kernel kernel, cl_uint index, const Buffer& buffer);
  // A buffer that may be absent: nullptr passes a NULL __global pointer (e.g. raycast without a skipping grid).
  static void setArg(cl_kernel kernel, cl_uint index, const Buffer* buffer);
  template <typename T>
  static void setArg(cl_kernel kernel, cl_uint index, const T& value) {
    static_assert(std::is_trivially_copyable_v<T> && !std::is_pointer_v<T>, "kernel arguments are plain values");
    check(clSetKernelArg(kernel, index, sizeof value, &value), "clSetKernelArg");
  }
  void enqueue(Stage stage, cl_kernel kernel, Size3 global, Size3 local);

  cl_device_id device_;
  Context context_;
  Queue queue_;
  std::map<cl_kernel, size_t> groupLimits_;  // CL_KERNEL_WORK_GROUP_SIZE per kernel
  std::vector<std::pair<Stage, Event>> pending_;
};

}  // namespace sb::opencl
