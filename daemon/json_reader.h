#pragma once
// Reads one JSON object into typed fields, once, with errors that name the key, the value and what is
// allowed. Every key the caller does not read is an error listing the known keys (finish()).
//
//   JsonObjectReader r(j, "config.json: socket");
//   r.string("path", cfg.path);
//   r.integer("max_clients", cfg.maxClients, 1, 4096);
//   r.finish();

#include <cstdint>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace sb::daemon {

class JsonObjectReader {
 public:
  // `where` prefixes every message (file and section). Throws sb::Error when `j` is not an object.
  JsonObjectReader(const nlohmann::json& j, std::string where);

  void string(const char* key, std::string& out);
  void boolean(const char* key, bool& out);
  void number(const char* key, double& out, double minimum, double maximum);
  void integer(const char* key, int64_t& out, int64_t minimum, int64_t maximum);
  template <typename T>
  void integer(const char* key, T& out, int64_t minimum, int64_t maximum) {
    int64_t v = static_cast<int64_t>(out);
    integer(key, v, minimum, maximum);
    out = static_cast<T>(v);
  }
  // A string that must be one of `allowed`.
  void choice(const char* key, std::string& out, std::initializer_list<const char*> allowed);
  // A nested object, or nullptr when the key is absent (marks the key as known either way).
  const nlohmann::json* object(const char* key);
  // Throws sb::Error for the first key that was never asked for.
  void finish() const;

  const std::string& where() const { return where_; }

 private:
  const nlohmann::json* find(const char* key);
  [[noreturn]] void fail(const char* key, const nlohmann::json& value, const std::string& allowed) const;

  const nlohmann::json& j_;
  std::string where_;
  std::set<std::string> known_;
};

}  // namespace sb::daemon
