#include "pipeline/opencl/device.h"

#include <algorithm>
#include <cctype>

#include "core/error.h"

namespace sb::opencl {

namespace {

bool isIndex(const std::string& s) {
  return !s.empty() && s.size() < 9 && std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); });
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool matches(const std::string& selector, int index, const std::string& name) {
  if (selector.empty()) return true;
  if (isIndex(selector)) return std::stoi(selector) == index;
  return lower(name).find(lower(selector)) != std::string::npos;
}

}  // namespace

std::string describeDevices(const std::vector<DeviceInfo>& devices) {
  if (devices.empty()) return "  (no OpenCL platform)\n";
  std::string out;
  for (const DeviceInfo& d : devices)
    out += "  [platform " + std::to_string(d.platformIndex) + "] " + d.platformName + " / [device " +
           std::to_string(d.deviceIndex) + "] " + d.deviceName + " (" + (d.gpu ? "GPU" : "CPU") + ", " + d.version +
           ")\n";
  return out;
}

DeviceInfo selectDevice(const std::vector<DeviceInfo>& devices, const std::string& platform,
                        const std::string& device) {
  std::vector<DeviceInfo> candidates;
  for (const DeviceInfo& d : devices)
    if (matches(platform, d.platformIndex, d.platformName)) candidates.push_back(d);
  if (candidates.empty())
    throw Error("opencl_platform '" + platform + "' matches no OpenCL platform; available:\n" +
                describeDevices(devices) + "set 'opencl_platform' to one of the indices or a part of a name");
  // Automatic platform: the first one that has a GPU, else the first.
  if (platform.empty()) {
    const auto gpu = std::find_if(candidates.begin(), candidates.end(), [](const DeviceInfo& d) { return d.gpu; });
    const int chosen = gpu != candidates.end() ? gpu->platformIndex : candidates.front().platformIndex;
    candidates.erase(std::remove_if(candidates.begin(), candidates.end(),
                                    [&](const DeviceInfo& d) { return d.platformIndex != chosen; }),
                     candidates.end());
  }
  std::vector<DeviceInfo> chosen;
  for (const DeviceInfo& d : candidates)
    if (matches(device, d.deviceIndex, d.deviceName)) chosen.push_back(d);
  if (chosen.empty())
    throw Error("opencl_device '" + device + "' matches no device of platform '" + candidates.front().platformName +
                "'; available:\n" + describeDevices(devices) +
                "set 'opencl_device' to one of the device indices or a part of a name");
  if (device.empty()) {
    const auto gpu = std::find_if(chosen.begin(), chosen.end(), [](const DeviceInfo& d) { return d.gpu; });
    if (gpu != chosen.end()) return *gpu;
  }
  return chosen.front();
}

}  // namespace sb::opencl
