#pragma once
// Reading a test's output files whole: text and JSON. Both throw std::runtime_error naming the file when it
// cannot be read, so a missing output fails the test with its path.

#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

namespace sb::test {

inline std::string readText(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read '" + path + "'");
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

inline nlohmann::json readJson(const std::string& path) { return nlohmann::json::parse(readText(path)); }

}  // namespace sb::test
