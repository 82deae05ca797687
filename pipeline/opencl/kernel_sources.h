#pragma once
// The OpenCL program text: the kernels/cl/*.cl wrappers with the kernels/*.h headers they include, embedded
// in the binary at build time (embed_sources.cmake) so that no file has to be installed beside it.

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace sb::opencl {

struct SourceFile {
  const char* path;  // relative to the source root, e.g. "kernels/cl/track.cl", "kernels/track.h"
  const char* text;
};

// Every embedded file: kernels/cl/*.cl and kernels/*.h.
const std::vector<SourceFile>& embeddedSources();

// Looks a file up by its path relative to the source root; nullopt when it does not exist.
using SourceLoader = std::function<std::optional<std::string>(const std::string& path)>;

SourceLoader embeddedLoader();

// Reads `directory`/path from disk (an install-time or development override of the embedded files).
SourceLoader directoryLoader(const std::string& directory);

// One program text from the .cl files `entries`: each `#include "path"` line is replaced by the file (each file
// at most once, as #pragma once would; `#pragma once` lines are dropped), with #line markers so that compiler
// messages name the original file and line. Throws sb::Error naming the including file and line when an
// include cannot be found.
std::string assembleProgram(const std::vector<std::string>& entries, const SourceLoader& load);

// The .cl files of the backend's program, in order.
const std::vector<std::string>& programEntries();

}  // namespace sb::opencl
