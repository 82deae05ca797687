#include "drivers/tum_index.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/input_file.h"

namespace sb {

namespace {

// The directory that holds the depth images in an associations file.
const char* const kDepthDir = "depth/";

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

std::string where(const std::string& path, size_t line) {
  return "'" + path + "' line " + std::to_string(line);
}

double parseTimestamp(const std::string& path, size_t line, const std::string& stamp) {
  double t = 0;
  size_t used = 0;
  try {
    t = std::stod(stamp, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != stamp.size() || !std::isfinite(t))
    throw Error(where(path, line) + ": timestamp \"" + stamp + "\" is not a number of seconds");
  return t;
}

}  // namespace

std::vector<TumIndexEntry> readTumIndex(const std::string& path, bool associations) {
  InputFile in(path, "frame index");
  const std::string expected = associations ? "`timestamp file timestamp file`" : "`timestamp filename`";
  std::vector<TumIndexEntry> entries;
  std::string raw;
  size_t lineNo = 0;
  while (std::getline(in, raw)) {
    ++lineNo;
    const std::string line = trim(raw);
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::vector<std::string> tokens;
    for (std::string t; fields >> t;) tokens.push_back(t);
    if (tokens.size() != (associations ? 4u : 2u))
      throw Error(where(path, lineNo) + ": expected " + expected + ", found \"" + line + "\"");
    size_t pair = 0;
    if (associations) {
      if (tokens[1].rfind(kDepthDir, 0) != 0) pair = 2;
      if (tokens[pair + 1].rfind(kDepthDir, 0) != 0)
        throw Error(where(path, lineNo) + ": neither file lies under " + kDepthDir + ", found \"" + line +
                    "\"");
    }
    TumIndexEntry e;
    e.line = lineNo;
    e.timestamp = parseTimestamp(path, lineNo, tokens[pair]);
    e.file = tokens[pair + 1];
    if (!entries.empty() && !(e.timestamp > entries.back().timestamp))
      throw Error(where(path, lineNo) + ": timestamp " + tokens[pair] + " does not increase (previous " +
                  std::to_string(entries.back().timestamp) + " at line " +
                  std::to_string(entries.back().line) + "); sort the index by time and remove duplicates");
    entries.push_back(std::move(e));
  }
  if (entries.empty()) throw Error("'" + path + "' lists no frames");
  return entries;
}

}  // namespace sb
