#include "drivers/sequence.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/image.h"
#include "core/error.h"
#include "core/input_file.h"
#include "drivers/bag_loader.h"
#include "drivers/prefetch_source.h"
#include "drivers/raw_reader.h"
#include "drivers/tum_layout.h"
#include "drivers/tum_reader.h"

namespace fs = std::filesystem;

namespace sb {

namespace {

// Largest image side accepted from the command line, pixels.
constexpr int kMaxSide = kMaxDepthImageSide;

void checkOptions(const std::string& path, const SequenceOptions& o) {
  const auto bad = [&](const std::string& what) {
    throw Error("opening '" + path + "': " + what + "; fix the command-line value");
  };
  if (o.depthScale && !(*o.depthScale > 0)) bad("depth scale must be > 0 raw units per metre");
  for (const auto* f : {&o.fx, &o.fy})
    if (*f && !(**f > 0)) bad("focal lengths must be > 0 pixels");
  for (const auto* c : {&o.cx, &o.cy})
    if (*c && !std::isfinite(**c)) bad("the principal point must be finite");
  for (const auto* s : {&o.width, &o.height})
    if (*s && (**s <= 0 || **s > kMaxSide))
      bad("image sides must be in [1, " + std::to_string(kMaxSide) + "] pixels");
}

std::unique_ptr<FrameSource> openUnbuffered(const std::string& path, const SequenceOptions& options) {
  std::error_code ec;
  const fs::path p(path);
  if (fs::is_directory(p, ec)) return std::make_unique<TumReader>(path, options);
  if (fs::is_regular_file(p, ec)) {
    if (p.extension() == ".raw") return std::make_unique<RawReader>(path, options);
    if (p.extension() == ".bag") return openBag(path, options);
    if (p.filename() == tum::kIndexFile) return std::make_unique<TumReader>(p.parent_path().string(), options);
    throw Error("cannot tell the format of '" + path +
                "': give a TUM-layout directory (with depth.txt), a SLAMBench file ending in .raw or a ROS bag "
                "ending in .bag");
  }
  // Missing, or a FIFO, socket, device, symlink loop or unreadable path: say which (never opened).
  throw Error("sequence " + quoteForMessage(path) + " " + pathProblem(path) +
              ": give a TUM-layout directory, a .raw file or a .bag file");
}

}  // namespace

std::unique_ptr<FrameSource> openSequence(const std::string& path, const SequenceOptions& options) {
  checkOptions(path, options);
  auto source = openUnbuffered(path, options);
  if (options.prefetch && options.prefetchDepth > 0)
    return std::make_unique<PrefetchSource>(std::move(source), options.prefetchDepth,
                                            std::max<size_t>(options.prefetchThreads, 1));
  return source;
}

}  // namespace sb
