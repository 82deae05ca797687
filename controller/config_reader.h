#pragma once
// Reads one JSON object of typed, range-checked settings. Each call names a key and where its value goes;
// finish() refuses keys nobody asked for. Every error names `where`, the key, the value and what is allowed:
//   ConfigReader r(section, "config.json: controller.slambooster");
//   r.number("v_stand_m_per_frame", c.vStand, 0.0, 1.0);
//   r.finish();

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace sb {

class ConfigReader {
 public:
  // `j` must be an object (or null, read as an empty object). Throws sb::Error otherwise.
  ConfigReader(const nlohmann::json& j, std::string where);

  // Each reads `key` when present (leaving `out` unchanged otherwise) and checks the closed range.
  void number(const std::string& key, double& out, double minimum, double maximum);
  void integer(const std::string& key, int& out, int minimum, int maximum);
  void boolean(const std::string& key, bool& out);
  void string(const std::string& key, std::string& out, const std::vector<std::string>& allowed = {});
  // A list of numbers / integers with minSize..maxSize entries, each in range.
  void numbers(const std::string& key, std::vector<double>& out, double minimum, double maximum, size_t minSize,
               size_t maxSize);
  void integers(const std::string& key, std::vector<int>& out, int minimum, int maximum, size_t minSize,
                size_t maxSize);
  // Marks `key` as known and returns its value, or nullptr when absent (for nested objects).
  const nlohmann::json* raw(const std::string& key);

  // Throws sb::Error naming the first key that no call above asked for, and listing the known keys.
  void finish() const;

  const std::string& where() const { return where_; }
  // An sb::Error message prefix for `key`: "<where>: 'key'".
  std::string at(const std::string& key) const;

 private:
  const nlohmann::json* find(const std::string& key);

  nlohmann::json j_;
  std::string where_;
  std::vector<std::string> known_;
};

}  // namespace sb
