#pragma once
// Reading a test's output files whole: text and JSON. Both throw std::runtime_error naming the file when it
// cannot be read, so a missing output fails the test with its path. dataLines counts a file's records.

#include <cstddef>
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

// The lines of `path` that are neither empty nor comments ("#"): a trajectory's poses, a log's records. 0 when
// the file cannot be read (a run that has not written it yet).
inline size_t dataLines(const std::string& path) {
  std::ifstream in(path);
  size_t n = 0;
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] != '#') ++n;
  return n;
}

}  // namespace sb::test
