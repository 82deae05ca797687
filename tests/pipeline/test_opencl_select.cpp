// The backend keys of the pipeline config, the choice of an OpenCL device by the selectors, and the assembly
// of the embedded OpenCL program text. No OpenCL platform needed.

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "pipeline/backend_factory.h"
#include "pipeline/config.h"
#include "pipeline/cpu/cpu_backend.h"
#include "pipeline/opencl/device.h"
#include "pipeline/opencl/kernel_sources.h"

using Catch::Matchers::Contains;

namespace {

sb::opencl::DeviceInfo fakeDevice(int platform, int device, const std::string& platformName, const std::string& name,
                                  bool gpu) {
  sb::opencl::DeviceInfo d;
  d.platformIndex = platform;
  d.deviceIndex = device;
  d.platformName = platformName;
  d.deviceName = name;
  d.gpu = gpu;
  d.version = "OpenCL 1.2";
  return d;
}

// A machine with PoCL first and an ODROID-like Mali second (the T628 MP6 as two devices: 4 + 2 cores).
std::vector<sb::opencl::DeviceInfo> fakeMachine() {
  return {fakeDevice(0, 0, "Portable Computing Language", "pthread-cortex-a15", false),
          fakeDevice(1, 0, "ARM Platform", "Mali-T628", true), fakeDevice(1, 1, "ARM Platform", "Mali-T628", true)};
}

}  // namespace

TEST_CASE("backend config keys parse, validate and round-trip", "[config][opencl]") {
  const sb::PipelineConfig defaults;
  CHECK(defaults.backend == sb::BackendKind::automatic);
  CHECK_FALSE(defaults.openclHalfStorage);
  const auto c = sb::parseConfig(nlohmann::json{{"backend", "opencl"},
                                                {"opencl_platform", "NVIDIA"},
                                                {"opencl_device", 1},
                                                {"opencl_half_storage", true}});
  CHECK(c.backend == sb::BackendKind::opencl);
  CHECK(c.openclPlatform == "NVIDIA");
  CHECK(c.openclDevice == "1");
  CHECK(c.openclHalfStorage);
  CHECK(sb::parseConfig(sb::configToJson(c)).backend == sb::BackendKind::opencl);
  CHECK(sb::configToJson(c)["opencl_device"] == "1");
  CHECK(sb::parseConfig(nlohmann::json{{"backend", "cpu"}}).backend == sb::BackendKind::cpu);
  CHECK(sb::parseConfig(nlohmann::json{{"backend", "auto"}}).backend == sb::BackendKind::automatic);

  CHECK_THROWS_WITH(sb::parseConfig(nlohmann::json{{"backend", "cuda"}}, {}, "my.json"),
                    Contains("my.json") && Contains("'backend'") && Contains("\"cuda\"") && Contains("opencl"));
  CHECK_THROWS_WITH(sb::parseConfig(nlohmann::json{{"opencl_device", -1}}), Contains("'opencl_device'"));
  CHECK_THROWS_WITH(sb::parseConfig(nlohmann::json{{"opencl_platform", 1.5}}), Contains("'opencl_platform'"));
  CHECK_THROWS_WITH(sb::parseConfig(nlohmann::json{{"opencl_half_storage", "yes"}}), Contains("true or false"));
  CHECK_THROWS_WITH(sb::parseConfig(nlohmann::json{{"backend", "cpu"}, {"opencl_half_storage", true}}),
                    Contains("'opencl_half_storage'") && Contains("cpu"));
}

TEST_CASE("selectDevice: automatic choice prefers a GPU platform, selectors by index or name", "[opencl][select]") {
  const auto devices = fakeMachine();
  const auto automatic = sb::opencl::selectDevice(devices, "", "");
  CHECK(automatic.platformIndex == 1);
  CHECK(automatic.deviceIndex == 0);
  CHECK(sb::opencl::selectDevice(devices, "0", "").deviceName == "pthread-cortex-a15");
  CHECK(sb::opencl::selectDevice(devices, "portable", "").platformIndex == 0);  // case-insensitive substring
  const auto second = sb::opencl::selectDevice(devices, "ARM", "1");
  CHECK(second.platformIndex == 1);
  CHECK(second.deviceIndex == 1);
  CHECK(sb::opencl::selectDevice(devices, "", "mali").platformIndex == 1);
  // Only CPU devices: the first one.
  const std::vector<sb::opencl::DeviceInfo> pocl = {devices[0]};
  CHECK_FALSE(sb::opencl::selectDevice(pocl, "", "").gpu);

  CHECK_THROWS_WITH(sb::opencl::selectDevice(devices, "NVIDIA", ""),
                    Contains("opencl_platform 'NVIDIA'") && Contains("Mali-T628") && Contains("[platform 0]"));
  CHECK_THROWS_WITH(sb::opencl::selectDevice(devices, "ARM", "2"),
                    Contains("opencl_device '2'") && Contains("ARM Platform"));
  CHECK_THROWS_WITH(sb::opencl::selectDevice({}, "", ""), Contains("no OpenCL platform"));
}

TEST_CASE("the embedded OpenCL program: includes resolved once, #line markers, missing files named",
          "[opencl][sources]") {
  const std::string program = sb::opencl::assembleProgram(sb::opencl::programEntries(), sb::opencl::embeddedLoader());
  for (const char* kernel : {"mm2metersKernel", "bilateralFilterKernel", "halfSampleRobustKernel", "depth2vertexKernel",
                             "vertex2normalKernel", "trackKernel", "reduceKernel", "integrateKernel", "raycastKernel",
                             "renderKernel"})
    CHECK_THAT(program, Contains(std::string("__kernel void ") + kernel));
  CHECK(program.find("#include \"") == std::string::npos);  // (<math.h> stays, in the C++-only branch)
  CHECK(program.find("#pragma once") == std::string::npos);
  // kernels/common.h is included by every header but appears once.
  const std::string marker = "#line 1 \"kernels/common.h\"";
  const size_t first = program.find(marker);
  REQUIRE(first != std::string::npos);
  CHECK(program.find(marker, first + 1) == std::string::npos);

  const sb::opencl::SourceLoader fake = [](const std::string& path) -> std::optional<std::string> {
    if (path == "a.cl") return std::string("// a\n#include \"b.h\"\nkernel_a\n");
    if (path == "b.h") return std::string("#pragma once\n#include \"missing.h\"\n");
    return std::nullopt;
  };
  CHECK_THROWS_WITH(sb::opencl::assembleProgram({"a.cl"}, fake), Contains("b.h:2") && Contains("'missing.h'"));
  const sb::opencl::SourceLoader ok = [](const std::string& path) -> std::optional<std::string> {
    if (path == "a.cl") return std::string("// a\n#include \"b.h\"\nkernel_a\n");
    if (path == "b.h") return std::string("#pragma once\nint b;\n");
    return std::nullopt;
  };
  CHECK(sb::opencl::assembleProgram({"a.cl"}, ok) ==
        "#line 1 \"a.cl\"\n// a\n#line 1 \"b.h\"\n\nint b;\n#line 3 \"a.cl\"\nkernel_a\n");
}

TEST_CASE("makeBackend: backend cpu is the CPU backend, without half precision", "[opencl][factory]") {
  sb::PipelineConfig config;
  config.backend = sb::BackendKind::cpu;
  config.volumeResolution = 64;
  sb::ThreadPool pool(1);
  auto backend = sb::makeBackend(config, sb::Intrinsics{}, pool);
  CHECK(dynamic_cast<sb::CpuBackend*>(backend.get()) != nullptr);
  CHECK_FALSE(backend->supportsHalfPrecision());
  CHECK_NOTHROW(backend->setHalfPrecision(false));
  CHECK_THROWS_WITH(backend->setHalfPrecision(true), Contains("backend opencl"));
}
