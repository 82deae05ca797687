#include "pipeline/opencl/cl_api.h"

#include <vector>

#include "core/error.h"
#include "pipeline/opencl/device.h"

namespace sb::opencl {

namespace {

std::vector<cl_platform_id> platforms() {
  cl_uint count = 0;
  const cl_int code = clGetPlatformIDs(0, nullptr, &count);
  // -1001 is CL_PLATFORM_NOT_FOUND_KHR: the ICD loader found no vendor.
  if (code == -1001 || (code == CL_SUCCESS && count == 0)) return {};
  check(code, "clGetPlatformIDs");
  std::vector<cl_platform_id> ids(count);
  check(clGetPlatformIDs(count, ids.data(), nullptr), "clGetPlatformIDs");
  return ids;
}

std::vector<cl_device_id> devices(cl_platform_id platform) {
  cl_uint count = 0;
  const cl_int code = clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, 0, nullptr, &count);
  if (code == CL_DEVICE_NOT_FOUND) return {};
  check(code, "clGetDeviceIDs");
  std::vector<cl_device_id> ids(count);
  check(clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, count, ids.data(), nullptr), "clGetDeviceIDs");
  return ids;
}

std::string platformString(cl_platform_id id, cl_platform_info what) {
  size_t size = 0;
  check(clGetPlatformInfo(id, what, 0, nullptr, &size), "clGetPlatformInfo");
  std::string s(size, '\0');
  check(clGetPlatformInfo(id, what, size, s.data(), nullptr), "clGetPlatformInfo");
  return s.c_str();
}

std::string deviceString(cl_device_id id, cl_device_info what) {
  size_t size = 0;
  check(clGetDeviceInfo(id, what, 0, nullptr, &size), "clGetDeviceInfo");
  std::string s(size, '\0');
  check(clGetDeviceInfo(id, what, size, s.data(), nullptr), "clGetDeviceInfo");
  return s.c_str();
}

template <typename T>
T deviceValue(cl_device_id id, cl_device_info what) {
  T value{};
  check(clGetDeviceInfo(id, what, sizeof value, &value, nullptr), "clGetDeviceInfo");
  return value;
}

bool hasExtension(const std::string& extensions, const std::string& name) {
  return (" " + extensions + " ").find(" " + name + " ") != std::string::npos;
}

}  // namespace

std::string errorName(cl_int code) {
  switch (code) {
#define SB_CL_ERROR(name) \
  case name:              \
    return #name;
    SB_CL_ERROR(CL_DEVICE_NOT_FOUND)
    SB_CL_ERROR(CL_DEVICE_NOT_AVAILABLE)
    SB_CL_ERROR(CL_COMPILER_NOT_AVAILABLE)
    SB_CL_ERROR(CL_MEM_OBJECT_ALLOCATION_FAILURE)
    SB_CL_ERROR(CL_OUT_OF_RESOURCES)
    SB_CL_ERROR(CL_OUT_OF_HOST_MEMORY)
    SB_CL_ERROR(CL_PROFILING_INFO_NOT_AVAILABLE)
    SB_CL_ERROR(CL_BUILD_PROGRAM_FAILURE)
    SB_CL_ERROR(CL_MAP_FAILURE)
    SB_CL_ERROR(CL_INVALID_VALUE)
    SB_CL_ERROR(CL_INVALID_DEVICE)
    SB_CL_ERROR(CL_INVALID_CONTEXT)
    SB_CL_ERROR(CL_INVALID_COMMAND_QUEUE)
    SB_CL_ERROR(CL_INVALID_MEM_OBJECT)
    SB_CL_ERROR(CL_INVALID_BUILD_OPTIONS)
    SB_CL_ERROR(CL_INVALID_PROGRAM_EXECUTABLE)
    SB_CL_ERROR(CL_INVALID_KERNEL_NAME)
    SB_CL_ERROR(CL_INVALID_KERNEL)
    SB_CL_ERROR(CL_INVALID_ARG_INDEX)
    SB_CL_ERROR(CL_INVALID_ARG_VALUE)
    SB_CL_ERROR(CL_INVALID_ARG_SIZE)
    SB_CL_ERROR(CL_INVALID_KERNEL_ARGS)
    SB_CL_ERROR(CL_INVALID_WORK_DIMENSION)
    SB_CL_ERROR(CL_INVALID_WORK_GROUP_SIZE)
    SB_CL_ERROR(CL_INVALID_WORK_ITEM_SIZE)
    SB_CL_ERROR(CL_INVALID_GLOBAL_OFFSET)
    SB_CL_ERROR(CL_INVALID_EVENT)
    SB_CL_ERROR(CL_INVALID_OPERATION)
    SB_CL_ERROR(CL_INVALID_BUFFER_SIZE)
    SB_CL_ERROR(CL_INVALID_GLOBAL_WORK_SIZE)
#undef SB_CL_ERROR
    default:
      return "error " + std::to_string(code);
  }
}

void check(cl_int code, const char* what) {
  if (code != CL_SUCCESS)
    throw Error(std::string("OpenCL: ") + what + " failed: " + errorName(code) + " (" + std::to_string(code) + ")");
}

std::vector<DeviceInfo> listDevices() {
  std::vector<DeviceInfo> out;
  const std::vector<cl_platform_id> ids = platforms();
  for (size_t p = 0; p < ids.size(); ++p) {
    const std::string platformName = platformString(ids[p], CL_PLATFORM_NAME);
    const std::vector<cl_device_id> devs = devices(ids[p]);
    for (size_t d = 0; d < devs.size(); ++d) {
      DeviceInfo info;
      info.platformIndex = static_cast<int>(p);
      info.deviceIndex = static_cast<int>(d);
      info.platformName = platformName;
      info.deviceName = deviceString(devs[d], CL_DEVICE_NAME);
      info.version = deviceString(devs[d], CL_DEVICE_VERSION);
      const auto type = deviceValue<cl_device_type>(devs[d], CL_DEVICE_TYPE);
      info.gpu = (type & (CL_DEVICE_TYPE_GPU | CL_DEVICE_TYPE_ACCELERATOR)) != 0;
      const std::string extensions = deviceString(devs[d], CL_DEVICE_EXTENSIONS);
      info.fp16 = hasExtension(extensions, "cl_khr_fp16");
      info.fp64 = hasExtension(extensions, "cl_khr_fp64");
      info.hostUnifiedMemory = deviceValue<cl_bool>(devs[d], CL_DEVICE_HOST_UNIFIED_MEMORY) == CL_TRUE;
      info.maxWorkGroupSize = deviceValue<size_t>(devs[d], CL_DEVICE_MAX_WORK_GROUP_SIZE);
      info.globalMemoryBytes = deviceValue<cl_ulong>(devs[d], CL_DEVICE_GLOBAL_MEM_SIZE);
      out.push_back(info);
    }
  }
  return out;
}

cl_device_id deviceId(int platformIndex, int deviceIndex) {
  const std::vector<cl_platform_id> ids = platforms();
  if (platformIndex < 0 || platformIndex >= static_cast<int>(ids.size()))
    throw Error("OpenCL platform " + std::to_string(platformIndex) + " no longer exists");
  const std::vector<cl_device_id> devs = devices(ids[platformIndex]);
  if (deviceIndex < 0 || deviceIndex >= static_cast<int>(devs.size()))
    throw Error("OpenCL device " + std::to_string(deviceIndex) + " of platform " + std::to_string(platformIndex) +
                " no longer exists");
  return devs[deviceIndex];
}

Program buildProgram(cl_context context, cl_device_id device, const std::string& source, const std::string& options) {
  const char* text = source.c_str();
  const size_t length = source.size();
  cl_int code = CL_SUCCESS;
  Program program(clCreateProgramWithSource(context, 1, &text, &length, &code));
  check(code, "clCreateProgramWithSource");
  code = clBuildProgram(program.get(), 1, &device, options.c_str(), nullptr, nullptr);
  if (code != CL_SUCCESS) {
    size_t size = 0;
    clGetProgramBuildInfo(program.get(), device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &size);
    std::string log(size, '\0');
    clGetProgramBuildInfo(program.get(), device, CL_PROGRAM_BUILD_LOG, size, log.data(), nullptr);
    throw Error("OpenCL: building the kernels (options '" + options + "') failed: " + errorName(code) + "\n" +
                log.c_str());
  }
  return program;
}

Kernel createKernel(cl_program program, const char* name) {
  cl_int code = CL_SUCCESS;
  Kernel kernel(clCreateKernel(program, name, &code));
  check(code, (std::string("clCreateKernel ") + name).c_str());
  return kernel;
}

Buffer createBuffer(cl_context context, cl_mem_flags flags, size_t bytes, const char* what) {
  cl_int code = CL_SUCCESS;
  Buffer buffer(clCreateBuffer(context, flags, bytes > 0 ? bytes : 1, nullptr, &code));
  check(code, (std::string("clCreateBuffer ") + what + " (" + std::to_string(bytes) + " bytes)").c_str());
  return buffer;
}

double eventMs(cl_event event) {
  cl_ulong start = 0, end = 0;
  check(clGetEventProfilingInfo(event, CL_PROFILING_COMMAND_START, sizeof start, &start, nullptr),
        "clGetEventProfilingInfo");
  check(clGetEventProfilingInfo(event, CL_PROFILING_COMMAND_END, sizeof end, &end, nullptr), "clGetEventProfilingInfo");
  return end > start ? static_cast<double>(end - start) * 1e-6 : 0.0;
}

}  // namespace sb::opencl
