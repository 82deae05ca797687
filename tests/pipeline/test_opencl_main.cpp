// Test main of the OpenCL device tests: they need an OpenCL platform. Without one the binary reports SKIPPED
// with the reason (exit 77, a skip for CTest), except when CI is set, where PoCL must be installed and a
// missing platform is a failure. Tests tagged [noplatform] run under OCL_ICD_VENDORS pointing at an empty
// directory and need no platform. [data] tests read ../shared/data as in tests/support/main.cpp.

#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <optional>

#include "core/error.h"
#include "tests/pipeline/test_opencl_support.h"
#include "tests/support/test_data.h"

namespace {
std::optional<sb::opencl::DeviceInfo> device;
}

const sb::opencl::DeviceInfo& sb::test::openclTestDevice() {
  if (!device) throw sb::Error("no OpenCL test device (run the binary through its main)");
  return *device;
}

int main(int argc, char** argv) {
  bool wantsData = false, noPlatform = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strstr(argv[i], "[data]") && !std::strstr(argv[i], "~[data]")) wantsData = true;
    if (std::strstr(argv[i], "[noplatform]") && !std::strstr(argv[i], "~[noplatform]")) noPlatform = true;
  }
  // A cross-compiled binary (armhf under qemu) has no OpenCL platform of its architecture to find: an armhf
  // PoCL cannot be installed beside the host toolchain (architecture.md D9). There a missing platform is a
  // skip even in CI; the native build runs these tests.
  const bool ci = std::getenv("CI") != nullptr && !SB_CROSS_COMPILED;
  if (!noPlatform) {
    std::string problem;
    try {
      const auto devices = sb::opencl::listDevices();
      if (devices.empty())
        problem = "no OpenCL platform (install pocl-opencl-icd: scripts/install_deps.sh)";
      else
        device = sb::opencl::selectDevice(devices, "", "");
    } catch (const sb::Error& e) {
      problem = e.what();
    }
    if (!device) {
      std::cerr << (ci ? "FAILED" : "SKIPPED") << ": " << problem
                << (ci ? "; CI is set, so PoCL must be installed and a missing platform is a failure"
                       : SB_CROSS_COMPILED ? " (cross-compiled test binary: the native build runs the OpenCL tests)" : "")
                << "\n";
      return ci ? 1 : 77;
    }
    std::cerr << "OpenCL test device: " << device->deviceName << " (" << device->platformName << ", "
              << device->version << (device->fp64 ? ", fp64" : "") << (device->fp16 ? ", fp16" : "") << ")\n";
  }
  if (wantsData && !sb::test::hasSharedData()) {
    std::cerr << (ci ? "FAILED" : "SKIPPED") << ": shared data not found at '" << sb::test::sharedDataDir()
              << "' (place ../shared/data beside the checkout or set SB_SHARED_DATA)"
              << (ci ? "; CI is set, so missing data is a failure" : "") << "\n";
    return ci ? 1 : 77;
  }
  return Catch::Session().run(argc, argv);
}
