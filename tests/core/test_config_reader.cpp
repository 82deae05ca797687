// ConfigReader, the one reader of JSON settings: typed, range-checked keys; every error names the file, the
// dotted key, the value, what is allowed and what to do. readJsonConfig: the one settings-file loader.

#include <catch2/catch.hpp>
#include <fstream>
#include <string>

#include "core/config_reader.h"
#include "core/error.h"
#include "tests/support/test_data.h"

using Catch::Matchers::Contains;
using nlohmann::json;

namespace {

// The message of the sb::Error that `f` throws, or "no error".
template <typename F>
std::string errorOf(F f) {
  try {
    f();
  } catch (const sb::Error& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("config reader: present keys are read, absent ones keep their value", "[core][config]") {
  const auto j = json::parse(R"({"a": 0.5, "f": 0.25, "n": 3, "u": 7, "b": true, "s": "x", "list": [1, 2],
                                 "names": ["p", "q"], "sub": {"k": 4}})");
  sb::ConfigReader r(j, "file.json");
  double a = 0, missing = 7;
  float f = 0;
  int n = 0, k = 0;
  size_t u = 0;
  bool b = false;
  std::string s;
  std::vector<int> list;
  std::vector<std::string> names;
  r.number("a", a, 0, 1);
  r.number("missing", missing, 0, 10);
  r.number("f", f, 0, 1);
  r.integer("n", n, 0, 5);
  r.integer("u", u, 0, 10);
  r.boolean("b", b);
  r.string("s", s, {"x", "y"});
  r.integers("list", list, 0, 9, 1, 4);
  r.strings("names", names, {"p", "q"}, 1);
  r.section("sub", [&](sb::ConfigReader& sub) { sub.integer("k", k, 0, 9); });
  REQUIRE_NOTHROW(r.finish());
  CHECK(a == 0.5);
  CHECK(missing == 7);
  CHECK(f == 0.25f);
  CHECK(n == 3);
  CHECK(u == 7);
  CHECK(b);
  CHECK(s == "x");
  CHECK(list == std::vector<int>{1, 2});
  CHECK(names == std::vector<std::string>{"p", "q"});
  CHECK(k == 4);
  CHECK_NOTHROW(sb::ConfigReader(json(), "null reads as empty").finish());
}

TEST_CASE("config reader: each error names the file, the key, the value, the range and the fix",
          "[core][config]") {
  const auto message = [](const char* text, auto read) {
    return errorOf([&] {
      sb::ConfigReader r(json::parse(text), "c.json", "controller.step");
      read(r);
      r.finish();
    });
  };
  double x = 0.5;
  int n = 3;
  bool b = false;
  std::string s = "a";
  std::vector<double> v{1};
  std::vector<std::string> names{"p"};
  // Out of range: file, dotted key, value, range, and the value kept without the key.
  CHECK_THAT(message(R"({"gain": 5})", [&](sb::ConfigReader& r) { r.number("gain", x, 0, 1); }),
             Contains("c.json: 'controller.step.gain' = 5 is not allowed: expected a number in [0, 1]") &&
                 Contains("fix the value or remove the key to keep 0.5"));
  // Wrong types.
  CHECK_THAT(message(R"({"gain": "high"})", [&](sb::ConfigReader& r) { r.number("gain", x, 0, 1); }),
             Contains("'controller.step.gain' = \"high\"") && Contains("expected a number in [0, 1]"));
  CHECK_THAT(message(R"({"frames": 1.5})", [&](sb::ConfigReader& r) { r.integer("frames", n, 0, 10); }),
             Contains("c.json: 'controller.step.frames' = 1.5") && Contains("an integer in [0, 10]") &&
                 Contains("keep 3"));
  CHECK_THAT(message(R"({"frames": 11})", [&](sb::ConfigReader& r) { r.integer("frames", n, 0, 10); }),
             Contains("'controller.step.frames' = 11") && Contains("[0, 10]"));
  CHECK_THAT(message(R"({"frames": 18446744073709551615})",
                     [&](sb::ConfigReader& r) { r.integer("frames", n, 0, 10); }),
             Contains("= 18446744073709551615") && Contains("[0, 10]"));
  CHECK_THAT(
      message(R"({"on": 1})", [&](sb::ConfigReader& r) { r.boolean("on", b); }),
      Contains("'controller.step.on' = 1") && Contains("expected true or false") && Contains("keep false"));
  CHECK_THAT(message(R"({"mode": "c"})",
                     [&](sb::ConfigReader& r) {
                       r.string("mode", s, {"a", "b"});
                     }),
             Contains("'controller.step.mode' = \"c\"") && Contains("one of \"a\", \"b\"") &&
                 Contains("keep \"a\""));
  CHECK_THAT(
      message(R"({"levels": [1, 20]})", [&](sb::ConfigReader& r) { r.numbers("levels", v, 0, 8, 1, 4); }),
      Contains("'controller.step.levels' = an array of 2 elements") && Contains("each in [0, 8]") &&
          Contains("entry 20"));
  CHECK_THAT(message(R"({"at": [0.5, 2, 0.3]})",
                     [&](sb::ConfigReader& r) { r.numbers("at", v, 0, 1, 3, 3, "fractions"); }),
             Contains("'controller.step.at' = an array of 3 elements") &&
                 Contains("expected a list of 3 numbers (fractions), each in [0, 1] (entry 2 is not)"));
  CHECK_THAT(message(R"({"rails": ["p", "cpu"]})",
                     [&](sb::ConfigReader& r) {
                       r.strings("rails", names, {"p", "q"});
                     }),
             Contains("'controller.step.rails'") && Contains("entry \"cpu\"") && Contains("\"p\", \"q\""));
  CHECK_THAT(
      message(R"({"sub": 5})", [&](sb::ConfigReader& r) { r.section("sub", [](sb::ConfigReader&) {}); }),
      Contains("c.json: 'controller.step.sub' = 5") && Contains("a JSON object"));
  // Unknown keys, at any depth, with the known ones and the fix.
  CHECK_THAT(message(R"({"gain": 0.5, "typo": 1})", [&](sb::ConfigReader& r) { r.number("gain", x, 0, 1); }),
             Contains("c.json: unknown key 'controller.step.typo'") &&
                 Contains("known keys of 'controller.step': gain") &&
                 Contains("fix its spelling or remove it"));
  CHECK_THAT(message(R"({"sub": {"kk": 1}})",
                     [&](sb::ConfigReader& r) {
                       r.section("sub", [&](sb::ConfigReader& s2) { s2.integer("k", n, 0, 9); });
                     }),
             Contains("unknown key 'controller.step.sub.kk'") && Contains("k"));
  // A check the caller makes.
  CHECK_THAT(message(R"({"max": 1})", [&](sb::ConfigReader& r) { r.fail("max", "a value >= 'min'"); }),
             Contains("c.json: 'controller.step.max' = 1 is not allowed: expected a value >= 'min'"));
  CHECK_THAT(message(R"({})", [&](sb::ConfigReader& r) { r.fail("path", "a power trace"); }),
             Contains("'controller.step.path' is not set: expected a power trace; add it"));
  // Not an object.
  CHECK_THAT(errorOf([] { sb::ConfigReader(json::parse("[1]"), "w.json"); }),
             Contains("w.json: the settings must be a JSON object") && Contains("an array of 1 elements"));
}

TEST_CASE("config reader: readJsonConfig keeps the file protections and refuses non-objects",
          "[core][config]") {
  const std::string dir = sb::test::scratchDir("config_reader");
  std::ofstream(dir + "/ok.json") << R"({"a": 1})";
  CHECK(sb::readJsonConfig(dir + "/ok.json", "config file")["a"] == 1);
  std::ofstream(dir + "/list.json") << "[1, 2]";
  CHECK_THAT(
      errorOf([&] { sb::readJsonConfig(dir + "/list.json", "config file"); }),
      Contains("config file '" + dir + "/list.json' must hold a JSON object") && Contains("fix the file"));
  std::ofstream(dir + "/bad.json") << "{\n  \"a\": 1,\n}";
  CHECK_THAT(errorOf([&] { sb::readJsonConfig(dir + "/bad.json", "power config"); }),
             Contains("power config '" + dir + "/bad.json': not valid JSON at line 3"));
  std::ofstream(dir + "/deep.json") << std::string(100, '[') << std::string(100, ']');
  CHECK_THAT(errorOf([&] { sb::readJsonConfig(dir + "/deep.json", "config file"); }),
             Contains("deeper than 64"));
  CHECK_THAT(errorOf([&] { sb::readJsonConfig(dir, "calibration"); }), Contains("is a directory"));
}
