#include "pipeline/opencl/kernel_sources.h"

#include <fstream>
#include <set>
#include <sstream>

#include "core/error.h"

namespace sb::opencl {

namespace {

// The path of an `#include "path"` line, or empty.
std::string includedPath(const std::string& line) {
  size_t i = line.find_first_not_of(" \t");
  if (i == std::string::npos || line[i] != '#') return "";
  i = line.find_first_not_of(" \t", i + 1);
  if (i == std::string::npos || line.compare(i, 7, "include") != 0) return "";
  const size_t open = line.find('"', i + 7);
  const size_t close = open == std::string::npos ? open : line.find('"', open + 1);
  if (close == std::string::npos) return "";
  return line.substr(open + 1, close - open - 1);
}

bool isPragmaOnce(const std::string& line) {
  std::istringstream in(line);
  std::string hash, pragma, once;
  in >> hash >> pragma >> once;
  return (hash == "#pragma" && pragma == "once") || (hash == "#" && pragma == "pragma" && once == "once");
}

void append(const std::string& path, const std::string& text, const SourceLoader& load, std::set<std::string>& seen,
            std::string& out) {
  out += "#line 1 \"" + path + "\"\n";
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const std::string include = includedPath(line);
    if (include.empty()) {
      out += isPragmaOnce(line) ? "\n" : line + "\n";
      continue;
    }
    if (seen.insert(include).second) {
      const std::optional<std::string> included = load(include);
      if (!included)
        throw Error("OpenCL program: " + path + ":" + std::to_string(number) + " includes '" + include +
                    "', which is not among the program's sources");
      append(include, *included, load, seen, out);
    }
    out += "#line " + std::to_string(number + 1) + " \"" + path + "\"\n";
  }
}

}  // namespace

SourceLoader embeddedLoader() {
  return [](const std::string& path) -> std::optional<std::string> {
    for (const SourceFile& f : embeddedSources())
      if (path == f.path) return std::string(f.text);
    return std::nullopt;
  };
}

SourceLoader directoryLoader(const std::string& directory) {
  return [directory](const std::string& path) -> std::optional<std::string> {
    std::ifstream in(directory + "/" + path);
    if (!in) return std::nullopt;
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  };
}

std::string assembleProgram(const std::vector<std::string>& entries, const SourceLoader& load) {
  std::set<std::string> seen;
  std::string out;
  for (const std::string& entry : entries) {
    if (!seen.insert(entry).second) continue;
    const std::optional<std::string> text = load(entry);
    if (!text) throw Error("OpenCL program: source '" + entry + "' not found");
    append(entry, *text, load, seen, out);
  }
  return out;
}

const std::vector<std::string>& programEntries() {
  static const std::vector<std::string> entries = {"kernels/cl/preprocess.cl", "kernels/cl/track.cl",
                                                   "kernels/cl/volume.cl", "kernels/cl/raycast.cl",
                                                   "kernels/cl/convert.cl"};
  return entries;
}

}  // namespace sb::opencl
