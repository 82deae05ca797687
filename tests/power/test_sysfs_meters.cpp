// INA231 (ODROID XU3 sysfs) and RAPL (powercap) against fake sysfs trees, including RAPL counter wrap-around.

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "power/clock.h"
#include "power/energy_counter.h"
#include "power/ina231.h"
#include "power/rapl.h"
#include "tests/support/test_data.h"

using namespace sb::power;
namespace fs = std::filesystem;

namespace {

void put(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
}
std::string get(const fs::path& file) {
  std::ifstream in(file);
  std::string s;
  in >> s;
  return s;
}

}  // namespace

TEST_CASE("ina231: enables the configured rails and sums sensor_W", "[power][ina231]") {
  const fs::path root = sb::test::scratchDir("power_ina231") + "/INA231";
  // Bus 3 as on the XU3; the memory rail already enabled (left alone), the others off.
  put(root / "3-0040/enable", "0\n");
  put(root / "3-0040/sensor_W", "1.234000\n");
  put(root / "3-0041/enable", "1\n");
  put(root / "3-0041/sensor_W", "0.120000\n");
  put(root / "3-0044/enable", "0\n");
  put(root / "3-0044/sensor_W", "0.500000\n");
  put(root / "3-0045/enable", "0\n");
  put(root / "3-0045/sensor_W", "0.080000\n");

  Ina231Settings c;
  c.root = root.string();
  c.rails = {"a15", "mem", "gpu"};
  ManualClock clock(7'000'000'000);
  auto meter = openIna231(c, {}, clock);
  CHECK(get(root / "3-0040/enable") == "1");
  CHECK(get(root / "3-0044/enable") == "1");
  CHECK(get(root / "3-0045/enable") == "0");  // a7 not configured
  CHECK(meter->info().kind == SampleKind::instantaneous);

  std::vector<PowerSample> samples;
  meter->poll(samples);
  REQUIRE(samples.size() == 1);
  CHECK(samples[0].watts == Approx(1.234 + 0.120 + 0.500));
  CHECK(samples[0].tNs == 7'000'000'000);
  meter->poll(samples);  // same clock time: no second sample at the same instant
  CHECK(samples.size() == 1);
  put(root / "3-0040/sensor_W", "2.000000\n");
  clock.advance(50'000'000);
  meter->poll(samples);
  REQUIRE(samples.size() == 2);
  CHECK(samples[1].watts == Approx(2.0 + 0.120 + 0.500));
}

TEST_CASE("ina231: a missing tree or rail is a clear error", "[power][ina231]") {
  const fs::path root = sb::test::scratchDir("power_ina231_missing") + "/INA231";
  Ina231Settings c;
  c.root = root.string();
  CHECK_THROWS_WITH(openIna231(c, {}, monotonicClock()), Catch::Contains("not an ODROID XU3") && Catch::Contains(root.string()));
  put(root / "3-0040/enable", "1\n");
  put(root / "3-0040/sensor_W", "1.0\n");
  c.rails = {"a15", "gpu"};
  CHECK_THROWS_WITH(openIna231(c, {}, monotonicClock()), Catch::Contains("rail 'gpu'") && Catch::Contains("0x0044"));
}

TEST_CASE("counter deltas wrap at max_energy_range_uj", "[power][rapl]") {
  CHECK(counterDelta(100, 250, 1000) == 150);
  CHECK(counterDelta(900, 50, 1000) == 150);   // 900 -> 1000 (wrap) -> 50
  CHECK(counterDelta(1000, 0, 1000) == 0);
  CHECK(counterDelta(900, 50, 0) == 50);       // range unknown: count from the wrap
}

TEST_CASE("rapl: interval-average power from energy_uj, summed over package zones, across a wrap", "[power][rapl]") {
  const fs::path root = sb::test::scratchDir("power_rapl") + "/powercap";
  const uint64_t range = 262143328850ull;
  put(root / "intel-rapl:0/energy_uj", std::to_string(range - 1'000'000) + "\n");
  put(root / "intel-rapl:0/max_energy_range_uj", std::to_string(range) + "\n");
  put(root / "intel-rapl:0:0/energy_uj", "5\n");  // a sub-zone (core) of package 0: not counted twice
  put(root / "intel-rapl:0:0/max_energy_range_uj", std::to_string(range) + "\n");
  put(root / "intel-rapl:1/energy_uj", "1000\n");
  put(root / "intel-rapl:1/max_energy_range_uj", std::to_string(range) + "\n");

  RaplSettings c;
  c.root = root.string();
  ManualClock clock(3'000'000'000);
  auto meter = openRapl(c, {}, clock);
  CHECK(meter->info().kind == SampleKind::intervalAverage);
  CHECK(meter->info().device.find("intel-rapl:0:0") == std::string::npos);
  CHECK(meter->info().device.find("intel-rapl:1") != std::string::npos);

  std::vector<PowerSample> samples;
  // 100 ms later: package 0 wrapped (1 J to the top, then 0.5 J), package 1 used 0.25 J -> 1.75 J / 0.1 s.
  put(root / "intel-rapl:0/energy_uj", "500000\n");
  put(root / "intel-rapl:1/energy_uj", "251000\n");
  clock.advance(100'000'000);
  meter->poll(samples);
  REQUIRE(samples.size() == 1);
  CHECK(samples[0].watts == Approx(17.5).epsilon(1e-12));
  CHECK(samples[0].tNs == 3'100'000'000);

  put(root / "intel-rapl:0/energy_uj", "1500000\n");
  put(root / "intel-rapl:1/energy_uj", "1251000\n");
  clock.advance(200'000'000);
  meter->poll(samples);
  REQUIRE(samples.size() == 2);
  CHECK(samples[1].watts == Approx(10.0).epsilon(1e-12));

  // Explicit zones.
  c.zones = {"intel-rapl:1"};
  auto one = openRapl(c, {}, clock);
  CHECK(one->info().device == (root / "intel-rapl:1").string());
}

TEST_CASE("rapl: no zones or unreadable counters are clear errors", "[power][rapl]") {
  const fs::path root = sb::test::scratchDir("power_rapl_empty") + "/powercap";
  fs::create_directories(root);
  RaplSettings c;
  c.root = root.string();
  CHECK_THROWS_WITH(openRapl(c, {}, monotonicClock()), Catch::Contains("no RAPL package zone"));
  c.root = (root / "absent").string();
  CHECK_THROWS_WITH(openRapl(c, {}, monotonicClock()), Catch::Contains("does not exist"));
  c.root = root.string();
  c.zones = {"intel-rapl:7"};
  CHECK_THROWS_WITH(openRapl(c, {}, monotonicClock()), Catch::Contains("intel-rapl:7/max_energy_range_uj"));
}
