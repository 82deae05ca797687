#include "pipeline/opencl/launcher.h"

#include <algorithm>

#include "core/error.h"

namespace sb::opencl {

Launcher::Launcher(const DeviceInfo& device) : device_(deviceId(device.platformIndex, device.deviceIndex)) {
  cl_int code = CL_SUCCESS;
  context_ = Context(clCreateContext(nullptr, 1, &device_, nullptr, nullptr, &code));
  check(code, "clCreateContext");
  queue_ = Queue(clCreateCommandQueue(context_.get(), device_, CL_QUEUE_PROFILING_ENABLE, &code));
  check(code, "clCreateCommandQueue");
}

void Launcher::setArg(cl_kernel kernel, cl_uint index, const Buffer& buffer) {
  const cl_mem mem = buffer.get();
  check(clSetKernelArg(kernel, index, sizeof mem, &mem), "clSetKernelArg");
}

void Launcher::setArg(cl_kernel kernel, cl_uint index, const Buffer* buffer) {
  if (buffer) return setArg(kernel, index, *buffer);
  check(clSetKernelArg(kernel, index, sizeof(cl_mem), nullptr), "clSetKernelArg");
}

size_t Launcher::maxGroupSize(cl_kernel kernel) {
  const auto it = groupLimits_.find(kernel);
  if (it != groupLimits_.end()) return it->second;
  size_t limit = 0;
  check(clGetKernelWorkGroupInfo(kernel, device_, CL_KERNEL_WORK_GROUP_SIZE, sizeof limit, &limit, nullptr),
        "clGetKernelWorkGroupInfo");
  groupLimits_[kernel] = limit;
  return limit;
}

void Launcher::enqueue(Stage stage, cl_kernel kernel, Size3 global, Size3 local) {
  // Halve the largest local dimension until the group fits the kernel's limit.
  const size_t limit = maxGroupSize(kernel);
  while (local[0] * local[1] * local[2] > limit) {
    const auto largest = std::max_element(local.begin(), local.end());
    if (*largest == 1) break;
    *largest /= 2;
  }
  for (int d = 0; d < 3; ++d) {
    local[d] = std::max<size_t>(1, std::min(local[d], global[d]));
    global[d] = (global[d] + local[d] - 1) / local[d] * local[d];
  }
  const cl_uint dims = global[2] > 1 ? 3 : (global[1] > 1 ? 2 : 1);
  cl_event event = nullptr;
  check(clEnqueueNDRangeKernel(queue_.get(), kernel, dims, nullptr, global.data(), local.data(), 0, nullptr, &event),
        "clEnqueueNDRangeKernel");
  pending_.emplace_back(stage, Event(event));
}

void Launcher::finish(StageTimes& times, Clock::time_point start) {
  check(clFinish(queue_.get()), "clFinish");
  const double hostMs = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  StageTimes device;
  for (const auto& [stage, event] : pending_) device[stage] += eventMs(event.get());
  double total = 0;
  for (double ms : device.ms) total += ms;
  for (int s = 0; s < kStageCount; ++s) {
    times.deviceMs[s] += device.ms[s];
    if (total > 0) times.ms[s] += hostMs * device.ms[s] / total;
  }
  if (total <= 0 && !pending_.empty()) times[pending_.front().first] += hostMs;
  pending_.clear();
}

}  // namespace sb::opencl
