#include "drivers/sequence.h"

#include <algorithm>
#include <filesystem>

#include "core/error.h"
#include "drivers/prefetch_source.h"
#include "drivers/raw_reader.h"
#include "drivers/tum_reader.h"

namespace fs = std::filesystem;

namespace sb {

namespace {

std::unique_ptr<FrameSource> openUnbuffered(const std::string& path, const SequenceOptions& options) {
  std::error_code ec;
  const fs::path p(path);
  if (fs::is_directory(p, ec)) return std::make_unique<TumReader>(path, options);
  if (fs::is_regular_file(p, ec)) {
    if (p.extension() == ".raw") return std::make_unique<RawReader>(path, options);
    if (p.filename() == "depth.txt") return std::make_unique<TumReader>(p.parent_path().string(), options);
    throw Error("cannot tell the format of '" + path +
                "': give a TUM-layout directory (with depth.txt) or a SLAMBench file ending in .raw");
  }
  throw Error("sequence '" + path + "' does not exist: give a TUM-layout directory or a .raw file");
}

}  // namespace

std::unique_ptr<FrameSource> openSequence(const std::string& path, const SequenceOptions& options) {
  auto source = openUnbuffered(path, options);
  if (options.prefetch && options.prefetchDepth > 0)
    return std::make_unique<PrefetchSource>(std::move(source), options.prefetchDepth,
                                            std::max<size_t>(options.prefetchThreads, 1));
  return source;
}

}  // namespace sb
