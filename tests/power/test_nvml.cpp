// NVML is loaded at run time: without the library the meter fails with an error that says what to install.
// On a machine with an NVIDIA driver the real library is exercised too.

#include <unistd.h>

#include <catch2/catch.hpp>
#include <memory>
#include <string>
#include <vector>

#include "core/error.h"
#include "power/clock.h"
#include "power/nvml.h"

using namespace sb::power;

TEST_CASE("nvml: an absent library is a clear error", "[power][nvml]") {
  NvmlSettings c;
  c.library = "libnvidia-ml-absent-for-test.so.1";
  try {
    openNvml(c, {}, monotonicClock());
    FAIL("expected an error");
  } catch (const sb::Error& e) {
    const std::string what = e.what();
    CHECK(what.find("libnvidia-ml-absent-for-test.so.1") != std::string::npos);
    CHECK(what.find("NVIDIA driver") != std::string::npos);
    CHECK(what.find("nvml.library") != std::string::npos);
  }
  c.library = "libc.so.6";  // loads, but is not NVML
  CHECK_THROWS_WITH(openNvml(c, {}, monotonicClock()), Catch::Contains("has no symbol nvmlInit_v2"));
}

TEST_CASE("nvml: the real library, when this machine has one", "[power][nvml]") {
  NvmlSettings c;
  std::unique_ptr<Meter> meter;
  try {
    meter = openNvml(c, {}, monotonicClock());
  } catch (const sb::Error& e) {
    WARN("NVML not usable here (" << e.what() << "): only the absence path is tested");
    return;
  }
  std::vector<PowerSample> samples;
  for (int i = 0; i < 20 && samples.size() < 3; ++i) {
    meter->poll(samples);
    usleep(50000);
  }
  REQUIRE(samples.size() >= 2);
  for (const PowerSample& s : samples) {
    CHECK(s.watts > 0.0);
    CHECK(s.watts < 2000.0);
  }
  WARN("NVML " << meter->info().device << " (" << sampleKindName(meter->info().kind) << "): " << samples.back().watts
               << " W");
}
