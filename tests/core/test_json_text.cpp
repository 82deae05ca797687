// JSON from untrusted places (core/json_text.h): nesting bounded before a value is built, errors with line
// and column, files that are directories refused by name, values quoted only as short flat excerpts.

#include <catch2/catch.hpp>
#include <fstream>
#include <string>

#include "core/error.h"
#include "core/config_reader.h"
#include "core/json_text.h"
#include "tests/support/test_data.h"

using Catch::Matchers::Contains;
using namespace sb;

namespace {

std::string nested(char open, size_t depth) {
  std::string s(depth, open);
  if (open == '{') {
    s.clear();
    for (size_t i = 0; i < depth; ++i) s += "{\"a\":";
  }
  return s;
}

}  // namespace

TEST_CASE("json_text: nesting deeper than the bound is refused with its position, not parsed",
          "[core][json]") {
  std::string error;
  CHECK(tryParseJson(std::string(kMaxJsonDepth, '[') + std::string(kMaxJsonDepth, ']'), error).has_value());
  CHECK_FALSE(tryParseJson(std::string(kMaxJsonDepth + 1, '[') + std::string(kMaxJsonDepth + 1, ']'), error)
                  .has_value());
  CHECK_THAT(error, Contains("deeper than 64 levels") && Contains("line 1, column 65"));
  // 100000 levels, closed or not: refused quickly, no stack overflow.
  CHECK_FALSE(tryParseJson("{\"unpin\":" + nested('[', 100000), error).has_value());
  CHECK_FALSE(tryParseJson(nested('{', 100000), error).has_value());
  CHECK_THAT(error, Contains("deeper than"));
  // Brackets inside strings do not count.
  CHECK(tryParseJson("[\"" + std::string(1000, '[') + "\\\"[\"]", error).has_value());
  CHECK_THROWS_WITH(parseJson("[[1]]", "x.json", 1),
                    Contains("x.json: arrays and objects nest deeper than 1"));
}

TEST_CASE("json_text: syntax errors give line and column", "[core][json]") {
  CHECK_THROWS_WITH(parseJson("{\n  \"a\": 1,\n  \"b\": tru\n}", "cfg.json"),
                    Contains("cfg.json: not valid JSON at line 3") && Contains("column"));
  CHECK_THROWS_WITH(parseJson("", "empty.json"), Contains("empty.json: not valid JSON at line 1"));
  // nlohmann quotes the last token, which may be the whole input: the message stays short.
  std::string error;
  CHECK_FALSE(tryParseJson("{\"" + std::string(100000, 'k') + "\x01\"}", error).has_value());
  CHECK(error.size() < 300);
}

TEST_CASE("json_text: files that are directories, missing or oversized are named", "[core][json]") {
  const std::string dir = test::scratchDir("json_text");
  CHECK_THROWS_WITH(readJsonConfig(dir, "config file"), Contains("config file '" + dir + "': it is a directory"));
  CHECK_THROWS_WITH(readJsonConfig(dir + "/absent.json", "calibration"),
                    Contains("cannot open calibration '" + dir + "/absent.json'"));
  std::ofstream(dir + "/big.json") << std::string(2000, ' ') << "{}";
  CHECK_THROWS_WITH(readTextFile(dir + "/big.json", "config file", 1000), Contains("is 2002 bytes"));
  std::ofstream(dir + "/ok.json") << "{\"a\": [1, 2]}";
  CHECK(readJsonConfig(dir + "/ok.json", "config file")["a"][1] == 2);
  std::ofstream(dir + "/deep.json") << nested('[', 70000);
  CHECK_THROWS_WITH(readJsonConfig(dir + "/deep.json", "config file"),
                    Contains("config file '" + dir + "/deep.json'") && Contains("deeper than"));
}

TEST_CASE("json_text: describeJson is short and flat", "[core][json]") {
  CHECK(describeJson(nlohmann::json(5)) == "5");
  CHECK(describeJson(nlohmann::json::array({1, 2, 3})) == "an array of 3 elements");
  CHECK(describeJson(nlohmann::json::object()) == "an object with 0 keys");
  CHECK(describeJson(nlohmann::json(std::string(1000, 'x'))).size() < 80);
}
