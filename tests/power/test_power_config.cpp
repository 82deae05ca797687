// The power config: config/power.json equals the built-in defaults and lists every key; bad input is refused
// with the key, the value and what is allowed.

#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "power/meter_registry.h"
#include "power/power_config.h"
#include "power/smartpower3.h"

using namespace sb::power;
using nlohmann::json;

TEST_CASE("config/power.json equals the built-in defaults and lists every key", "[power][config]") {
  PowerConfig start;
  start.meter = "rapl";  // values the file must overwrite
  start.meters["smartpower3"]["baud"] = 115200;
  const PowerConfig fromFile = loadPowerConfig(SB_POWER_CONFIG, start);
  CHECK(powerConfigToJson(fromFile) == powerConfigToJson(PowerConfig{}));

  std::ifstream in(SB_POWER_CONFIG);
  const json file = json::parse(in);
  const json expected = powerConfigToJson(PowerConfig{});
  for (const auto& item : expected.items()) {
    INFO(item.key());
    REQUIRE(file.contains(item.key()));
    if (item.value().is_object())
      for (const auto& sub : item.value().items()) {
        INFO(sub.key());
        CHECK(file[item.key()].contains(sub.key()));
      }
  }
}

TEST_CASE("power config: a partial file overrides only its keys", "[power][config]") {
  const PowerConfig c = parsePowerConfig(
      json::parse(R"({"meter": "smartpower3", "smartpower3": {"channel": "both"}, "idle_baseline_s": 5})"));
  CHECK(c.meter == "smartpower3");
  CHECK(c.meters["smartpower3"]["channel"] == "both");
  CHECK(c.meters["smartpower3"]["baud"] == 921600);
  CHECK(c.idleBaselineS == 5.0);
  CHECK(parsePowerConfig(powerConfigToJson(c)).meters["smartpower3"]["channel"] == "both");
}

TEST_CASE("power config: errors name the key, the value and what is allowed", "[power][config]") {
  auto error = [](const char* text) {
    try {
      parsePowerConfig(json::parse(text), {}, "power.json");
    } catch (const sb::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK_THAT(error(R"({"meter": "smartpower4"})"),
             Catch::Contains("power.json") && Catch::Contains("smartpower4") && Catch::Contains("smartpower3"));
  CHECK_THAT(error(R"({"metre": "none"})"), Catch::Contains("unknown key 'metre'") && Catch::Contains("meter"));
  CHECK_THAT(error(R"({"smartpower3": {"chanel": "1"}})"),
             Catch::Contains("unknown key 'smartpower3.chanel'") && Catch::Contains("channel"));
  CHECK_THAT(error(R"({"smartpower3": {"channel": "3"}})"), Catch::Contains("'smartpower3.channel'") && Catch::Contains("\"3\""));
  CHECK_THAT(error(R"({"smartpower3": {"baud": 1000000}})"), Catch::Contains("'smartpower3.baud' = 1000000"));
  CHECK_THAT(error(R"({"smartpower2": {"baud": 100000}})"), Catch::Contains("smartpower2.baud"));
  CHECK_THAT(error(R"({"smartpower2": {"baud": "fast"}})"), Catch::Contains("'smartpower2.baud' = \"fast\""));
  CHECK_THAT(error(R"({"ina231": {"rails": ["a15", "cpu"]}})"), Catch::Contains("'ina231.rails'") && Catch::Contains("\"cpu\"") &&
                                                                     Catch::Contains("\"a15\", \"a7\", \"gpu\", \"mem\""));
  CHECK_THAT(error(R"({"ina231": {"rails": []}})"), Catch::Contains("'ina231.rails' = an array of 0 elements") && Catch::Contains("at least 1"));
  CHECK_THAT(error(R"({"idle_baseline_s": -1})"), Catch::Contains("'idle_baseline_s' = -1"));
  CHECK_THAT(error(R"({"meter": "file"})"), Catch::Contains("file.path"));
  CHECK_THAT(error(R"({"rapl": 5})"), Catch::Contains("'rapl' = 5") && Catch::Contains("a JSON object"));
  CHECK_THAT(error(R"({"reopen_min_ms": 500, "reopen_max_ms": 100})"), Catch::Contains("reopen_max_ms"));
  CHECK_THAT(error(R"([1, 2])"), Catch::Contains("must be a JSON object"));
}

TEST_CASE("power config: every registered meter name is accepted", "[power][config]") {
  for (const std::string& name : meterNames()) {
    json j = {{"meter", name}};
    if (name == "file") j["file"] = {{"path", "trace.csv"}};
    CHECK(parsePowerConfig(j).meter == name);
  }
  CHECK(meterNames().size() == 8);
}

TEST_CASE("power config: a meter's settings come from its own parser", "[power][config]") {
  // The registry entry reads the section with the meter's settings struct (smartpower3.h), defaults filled in.
  const MeterType* type = findMeterType("smartpower3");
  REQUIRE(type != nullptr);
  REQUIRE(type->readSettings);
  sb::ConfigReader section(json{{"channel", "both"}}, "test", "smartpower3");
  SmartPower3Settings expected;
  expected.channel = "both";
  CHECK(type->readSettings(section, true) == expected.toJson());
  // parsePowerConfig hands each section to that parser: what it stores is the meter's own reading.
  const PowerConfig c = parsePowerConfig(json{{"meter", "smartpower3"}, {"smartpower3", {{"channel", "both"}}}});
  CHECK(c.meters["smartpower3"] == expected.toJson());
  CHECK(powerConfigToJson(PowerConfig{})["smartpower3"] == SmartPower3Settings{}.toJson());
  // The meter's own checks (a baud rate in range that the serial port does not offer) name the dotted key.
  sb::ConfigReader odd(json{{"baud", 100000}}, "power.json", "smartpower3");
  SmartPower3Settings s;
  CHECK_THROWS_WITH(s.read(odd, false), Catch::Contains("power.json: 'smartpower3.baud' = 100000") &&
                                            Catch::Contains("supported baud rate"));
  // Every meter with settings has its section; "none" has none.
  for (const MeterType& t : meterTypes()) CHECK(powerConfigToJson(PowerConfig{}).contains(t.name) == bool(t.readSettings));
  CHECK_FALSE(findMeterType("none")->readSettings);
}
