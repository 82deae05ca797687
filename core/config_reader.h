#pragma once
// The one reader of JSON settings (pipeline, controller, daemon, power and calibration files). Each call
// names a key and where its value goes; absent keys leave the value as it is (the default, or what a base
// config set); finish() refuses keys nobody asked for. Every error has one shape, naming the file, the dotted
// key, the value, what is allowed and what to do:
//   slamboosterd.json: 'socket.max_clients' = 0 is not allowed: expected an integer in [1, 4096]; fix the
//   value or remove the key to keep 128
//
//   ConfigReader r(j, "config.json");          // or ConfigReader(j, "config.json", "socket") for a section
//   r.integer("max_clients", c.maxClients, 1, 4096);
//   r.section("camera", [&](ConfigReader& s) { s.integer("fps", c.fps, 1, 1000); });
//   r.finish();
//
// Files: readJsonConfig() below (bounded nesting, line and column on syntax errors, objects only).

#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace sb {

class ConfigReader {
 public:
  // `j` must be an object (null reads as an empty object), else sb::Error. `where` (the file, or the file and
  // a section, e.g. "config.json: controller.step") starts every message; `path` is the dotted path of `j` in
  // its file ("" at the top level) and prefixes the keys the messages name.
  ConfigReader(const nlohmann::json& j, std::string where, std::string path = {});

  // Each reads `key` when present (leaving `out` unchanged otherwise) and checks the type and closed range.
  void number(const std::string& key, double& out, double minimum, double maximum);
  void number(const std::string& key, float& out, double minimum, double maximum);
  template <typename Int>
  void integer(const std::string& key, Int& out, int64_t minimum, int64_t maximum) {
    int64_t v = static_cast<int64_t>(out);
    if (readInteger(key, v, minimum, maximum)) out = static_cast<Int>(v);
  }
  void boolean(const std::string& key, bool& out);
  // A string; when `allowed` is not empty, one of those.
  void string(const std::string& key, std::string& out, const std::vector<std::string>& allowed = {});
  // Lists with minSize..maxSize entries, each in range (or, for strings, one of `allowed` when given).
  // `meaning` (e.g. "fractions of the volume side") is added to what the error says is expected.
  void numbers(const std::string& key, std::vector<double>& out, double minimum, double maximum,
               size_t minSize, size_t maxSize, const std::string& meaning = {});
  void integers(const std::string& key, std::vector<int>& out, int minimum, int maximum, size_t minSize,
                size_t maxSize);
  void strings(const std::string& key, std::vector<std::string>& out,
               const std::vector<std::string>& allowed = {}, size_t minSize = 0,
               size_t maxSize = std::numeric_limits<size_t>::max());

  // Marks `key` as known and returns its value, or nullptr when absent (for values read by the caller).
  const nlohmann::json* raw(const std::string& key);
  // The same for a nested object: any other value is an error.
  const nlohmann::json* object(const std::string& key);
  // Calls read(ConfigReader&) on the nested object `key` when present, then refuses its unknown keys.
  template <typename Read>
  void section(const std::string& key, Read read) {
    if (const nlohmann::json* v = object(key)) {
      ConfigReader sub(*v, where_, path(key));
      read(sub);
      sub.finish();
    }
  }

  // Throws sb::Error naming the first key that no call above asked for, and listing the known keys.
  void finish() const;

  // The error for a value the caller checks itself: "<where>: '<path.key>' = <value in the JSON> is not
  // allowed: expected <expected>; fix the value" (or "... is not set ..." when the key is absent).
  [[noreturn]] void fail(const std::string& key, const std::string& expected) const;

  const std::string& where() const { return where_; }
  // "<where>: '<path.key>'", the start of a message about `key`.
  std::string at(const std::string& key) const;
  // The dotted path of `key` ("socket.mode").
  std::string path(const std::string& key) const;

 private:
  const nlohmann::json* find(const std::string& key);
  bool readInteger(const std::string& key, int64_t& out, int64_t minimum, int64_t maximum);
  [[noreturn]] void reject(const std::string& key, const nlohmann::json& value, const std::string& expected,
                           const std::string& current) const;

  nlohmann::json j_;
  std::string where_, path_;
  std::vector<std::string> known_;
};

// Reads a settings file: bounded nesting (kMaxJsonDepth), "not valid JSON at line L, column C", a refusal of
// directories and other non-regular files, and of any top-level value but an object. `what` names the kind of
// file in messages ("config file", "calibration"). Throws sb::Error "<what> '<path>': ...".
nlohmann::json readJsonConfig(const std::string& path, const std::string& what);

}  // namespace sb
