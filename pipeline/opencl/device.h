#pragma once
// OpenCL devices as plain data (no OpenCL types): what the ICD loader lists, and the choice of one by the
// config's opencl_platform / opencl_device selectors.

#include <cstdint>
#include <string>
#include <vector>

namespace sb::opencl {

struct DeviceInfo {
  int platformIndex = 0;        // in the ICD loader's platform list
  int deviceIndex = 0;          // within the platform
  std::string platformName;     // e.g. "Portable Computing Language", "NVIDIA CUDA", "ARM Platform"
  std::string deviceName;       // e.g. "NVIDIA H100", "Mali-T628"
  std::string version;          // CL_DEVICE_VERSION
  bool gpu = false;             // a GPU or accelerator (not a CPU device such as PoCL's)
  bool fp16 = false;            // cl_khr_fp16: half arithmetic
  bool fp64 = false;            // cl_khr_fp64: the ICP sums are added in double on the device
  bool hostUnifiedMemory = false;  // CL_DEVICE_HOST_UNIFIED_MEMORY: mapped buffers are zero-copy
  size_t maxWorkGroupSize = 0;
  uint64_t globalMemoryBytes = 0;
};

// Every device of every platform. Empty when the loader finds no platform (no ICD installed); throws sb::Error
// on other OpenCL failures.
std::vector<DeviceInfo> listDevices();

// One line per device: "[platform 0] Portable Computing Language / [device 0] pthread-... (CPU, OpenCL 3.0)".
std::string describeDevices(const std::vector<DeviceInfo>& devices);

// The device chosen by the selectors (each an index or a case-insensitive name substring; empty = automatic:
// the first platform with a GPU, else the first platform; in it the first GPU, else the first device).
// Throws sb::Error listing the devices when none matches.
DeviceInfo selectDevice(const std::vector<DeviceInfo>& devices, const std::string& platform,
                        const std::string& device);

}  // namespace sb::opencl
