#pragma once
// The one place that includes the OpenCL headers: error checking and RAII handles for the cl_* objects the
// backend owns. Included only by the .cpp files of pipeline/opencl/.

#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include <string>
#include <utility>

namespace sb::opencl {

// "CL_OUT_OF_RESOURCES" for -5, "error -1234" for codes it does not know.
std::string errorName(cl_int code);

// Throws sb::Error "OpenCL: <what> failed: <error name> (<code>)" unless code is CL_SUCCESS.
void check(cl_int code, const char* what);

// Owns one OpenCL object and releases it with its clRelease* function. Movable, not copyable.
template <typename T, cl_int(CL_API_CALL* Release)(T)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(T handle) : handle_(handle) {}
  ~Handle() { reset(); }
  Handle(Handle&& other) noexcept : handle_(std::exchange(other.handle_, nullptr)) {}
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      reset();
      handle_ = std::exchange(other.handle_, nullptr);
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;

  T get() const { return handle_; }
  explicit operator bool() const { return handle_ != nullptr; }
  void reset() {
    if (handle_) Release(handle_);
    handle_ = nullptr;
  }

 private:
  T handle_ = nullptr;
};

using Context = Handle<cl_context, clReleaseContext>;
using Queue = Handle<cl_command_queue, clReleaseCommandQueue>;
using Program = Handle<cl_program, clReleaseProgram>;
using Kernel = Handle<cl_kernel, clReleaseKernel>;
using Buffer = Handle<cl_mem, clReleaseMemObject>;
using Event = Handle<cl_event, clReleaseEvent>;

// The cl_device_id of a device listed by listDevices() (device.h), by its indices.
cl_device_id deviceId(int platformIndex, int deviceIndex);

// Builds `source` for `device` with `options`; throws sb::Error with the build log on failure.
Program buildProgram(cl_context context, cl_device_id device, const std::string& source, const std::string& options);

Kernel createKernel(cl_program program, const char* name);
Buffer createBuffer(cl_context context, cl_mem_flags flags, size_t bytes, const char* what);

// Milliseconds between an event's start and end (it must have completed on a profiling queue).
double eventMs(cl_event event);

}  // namespace sb::opencl
