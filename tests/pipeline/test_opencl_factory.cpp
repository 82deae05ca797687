// makeBackend with OpenCL present (the test device) and absent ([noplatform]: run with OCL_ICD_VENDORS pointing
// at an empty directory, so the ICD loader finds no platform), and the program built from opencl_source_dir.

#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "pipeline/backend_factory.h"
#include "pipeline/cpu/cpu_backend.h"
#include "pipeline/opencl/kernel_sources.h"
#include "pipeline/opencl/opencl_backend.h"
#include "tests/pipeline/test_opencl_support.h"
#include "tests/support/test_data.h"

using Catch::Matchers::Contains;

namespace {

// Captures what spdlog's default logger writes while it lives.
class LogCapture {
 public:
  LogCapture() : previous_(spdlog::default_logger()) {
    auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(text_);
    spdlog::set_default_logger(std::make_shared<spdlog::logger>("capture", sink));
  }
  ~LogCapture() { spdlog::set_default_logger(previous_); }
  std::string text() const { return text_.str(); }
  size_t warnings() const {
    size_t count = 0;
    const std::string s = text_.str();
    for (size_t at = s.find("[warning]"); at != std::string::npos; at = s.find("[warning]", at + 1)) ++count;
    return count;
  }

 private:
  std::ostringstream text_;
  std::shared_ptr<spdlog::logger> previous_;
};

sb::PipelineConfig smallConfig(sb::BackendKind backend) {
  sb::PipelineConfig c;
  c.backend = backend;
  c.volumeResolution = 32;
  return c;
}

sb::Intrinsics smallImage() {
  sb::Intrinsics k;
  k.width = 64;
  k.height = 48;
  k.fx = k.fy = 50;
  k.cx = 31.5f;
  k.cy = 23.5f;
  return k;
}

}  // namespace

TEST_CASE("makeBackend: backend opencl runs on the selected device, with half storage on request",
          "[opencl][factory]") {
  const sb::opencl::DeviceInfo& device = sb::test::openclTestDevice();
  sb::PipelineConfig config = smallConfig(sb::BackendKind::opencl);
  config.openclPlatform = std::to_string(device.platformIndex);
  config.openclDevice = device.deviceName;
  config.openclHalfStorage = true;
  sb::ThreadPool pool(1);
  auto backend = sb::makeBackend(config, smallImage(), pool);
  auto* cl = dynamic_cast<sb::OpenClBackend*>(backend.get());
  REQUIRE(cl != nullptr);
  CHECK(cl->device().deviceName == device.deviceName);
  CHECK(backend->supportsHalfPrecision());
  CHECK(backend->halfPrecision());

  config.openclPlatform = "no-such-platform";
  CHECK_THROWS_WITH(sb::makeBackend(config, smallImage(), pool),
                    Contains("'no-such-platform'") && Contains(device.deviceName));
}

TEST_CASE("makeBackend: auto takes an OpenCL GPU, else falls back to the CPU backend with one warning",
          "[opencl][factory]") {
  const sb::opencl::DeviceInfo& device = sb::test::openclTestDevice();
  sb::ThreadPool pool(1);
  LogCapture log;
  auto backend = sb::makeBackend(smallConfig(sb::BackendKind::automatic), smallImage(), pool);
  INFO(log.text());
  if (device.gpu) {
    CHECK(dynamic_cast<sb::OpenClBackend*>(backend.get()) != nullptr);
    CHECK(log.warnings() == 0);
  } else {
    CHECK(dynamic_cast<sb::CpuBackend*>(backend.get()) != nullptr);
    CHECK(log.warnings() == 1);
    CHECK_THAT(log.text(), Contains("no OpenCL GPU") && Contains("cpu backend"));
  }
  // auto with the device named explicitly uses it, GPU or not.
  sb::PipelineConfig named = smallConfig(sb::BackendKind::automatic);
  named.openclDevice = device.deviceName;
  CHECK(dynamic_cast<sb::OpenClBackend*>(sb::makeBackend(named, smallImage(), pool).get()) != nullptr);
}

TEST_CASE("makeBackend without any OpenCL platform: auto warns once and runs on the CPU, opencl fails clearly",
          "[noplatform]") {
  REQUIRE(sb::opencl::listDevices().empty());  // this test runs with OCL_ICD_VENDORS set to an empty directory
  sb::ThreadPool pool(1);
  {
    LogCapture log;
    auto backend = sb::makeBackend(smallConfig(sb::BackendKind::automatic), smallImage(), pool);
    INFO(log.text());
    CHECK(dynamic_cast<sb::CpuBackend*>(backend.get()) != nullptr);
    CHECK(log.warnings() == 1);
    CHECK_THAT(log.text(), Contains("no OpenCL platform found") && Contains("cpu backend"));
  }
  CHECK_THROWS_WITH(sb::makeBackend(smallConfig(sb::BackendKind::opencl), smallImage(), pool),
                    Contains("backend opencl: no OpenCL platform found") && Contains("install") &&
                        Contains("'backend' to cpu"));
}

TEST_CASE("opencl_source_dir: the program is built from files on disk instead of the embedded copy",
          "[opencl][sources]") {
  const std::string dir = sb::test::scratchDir("opencl_source_dir");
  for (const sb::opencl::SourceFile& f : sb::opencl::embeddedSources()) {
    std::filesystem::create_directories(std::filesystem::path(dir + "/" + f.path).parent_path());
    std::ofstream(dir + "/" + f.path) << f.text;
  }
  sb::PipelineConfig config = smallConfig(sb::BackendKind::opencl);
  config.openclSourceDir = dir;
  CHECK_NOTHROW(sb::OpenClBackend(config, smallImage(), sb::test::openclTestDevice()));
  // A broken kernel on disk: the build log names the file (the #line markers keep the original names).
  std::ofstream(dir + "/kernels/cl/convert.cl", std::ios::app) << "\nthis is not OpenCL C;\n";
  CHECK_THROWS_WITH(sb::OpenClBackend(config, smallImage(), sb::test::openclTestDevice()),
                    Contains("building the kernels") && Contains("convert.cl"));
  std::filesystem::remove(dir + "/kernels/track.h");
  CHECK_THROWS_WITH(sb::OpenClBackend(config, smallImage(), sb::test::openclTestDevice()),
                    Contains("kernels/track.h") && Contains(dir));
}
