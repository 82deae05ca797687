#include "drivers/bag_loader.h"

#include <dlfcn.h>

#include <spdlog/spdlog.h>

#include <filesystem>
#include <memory>
#include <mutex>
#include <vector>

#include "core/error.h"
#include "drivers/camera_bounds.h"
#include "drivers/stamp_gate.h"
#include "drivers/bag_plugin.h"

namespace sb {

namespace {

namespace fs = std::filesystem;

struct LoadedPlugin {
  SbOpenBagFn open = nullptr;
  SbReadBagOdometryFn odometry = nullptr;
  std::string error;  // why it could not be loaded (then open is null)
};

bool under(const fs::path& path, const fs::path& dir) {
  const auto rel = path.lexically_normal().lexically_relative(fs::path(dir).lexically_normal());
  return !rel.empty() && *rel.begin() != "..";
}

std::vector<std::string> candidates() {
  std::vector<std::string> paths;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  // A build tree's executables use the build tree's plugin (never an older installed one).
  if (!ec && under(exe, SB_BUILD_DIR)) paths.push_back(std::string(SB_BAG_PLUGIN_BUILD_DIR) + "/" + kBagPluginFile);
  paths.push_back(std::string(SB_BAG_PLUGIN_INSTALL_DIR) + "/" + kBagPluginFile);
  return paths;
}

LoadedPlugin load() {
  LoadedPlugin plugin;
  std::string tried;
  for (const auto& path : candidates()) {
    tried += (tried.empty() ? "" : ", ") + path;
    std::error_code ec;
    if (!fs::exists(path, ec)) continue;
    // Never unloaded: the sources it creates must outlive any caller.
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      plugin.error = "the bag plugin '" + path + "' does not load: " + dlerror() +
                     " (are the ROS libraries it was built against installed? scripts/install_deps.sh)";
      return plugin;
    }
    const auto abi = reinterpret_cast<SbBagPluginAbiFn>(dlsym(handle, kBagPluginAbiSymbol));
    const auto open = reinterpret_cast<SbOpenBagFn>(dlsym(handle, kBagPluginOpenSymbol));
    const auto odometry = reinterpret_cast<SbReadBagOdometryFn>(dlsym(handle, kBagPluginOdometrySymbol));
    if (!abi || !open || !odometry || abi() != kBagPluginAbi) {
      plugin.error = "the bag plugin '" + path + "' is of another version than this program (ABI " +
                     (abi ? std::to_string(abi()) : std::string("unknown")) + ", expected " +
                     std::to_string(kBagPluginAbi) + "): install matching slambooster and slambooster-ros";
      return plugin;
    }
    plugin.open = open;
    plugin.odometry = odometry;
    return plugin;
  }
  plugin.error = "reading ROS bag files needs the bag plugin (" + std::string(kBagPluginFile) +
                 "), which is not installed (looked for " + tried +
                 "): install the slambooster-ros package, or build with ROS 1 installed (scripts/install_deps.sh)";
  return plugin;
}

const LoadedPlugin& plugin() {
  static std::once_flag once;
  static LoadedPlugin loaded;
  std::call_once(once, [] { loaded = load(); });
  return loaded;
}

}  // namespace

namespace {

// The bag's frames with their stamps checked as trajectory.tum's reader checks them (drivers/stamp_gate.h):
// a frame whose stamp does not increase, or is out of range, is dropped with a warning (the first few, then
// a count at the end).
class StampCheckedBag : public FrameSource {
 public:
  StampCheckedBag(std::unique_ptr<FrameSource> bag, std::string path) : bag_(std::move(bag)), path_(std::move(path)) {}
  ~StampCheckedBag() override {
    if (gate_.refused() > kWarnings)
      spdlog::warn("bag '{}': {} frames dropped in all for their stamps", path_, gate_.refused());
  }
  const SequenceInfo& info() const override { return bag_->info(); }
  std::optional<DepthFrame> next() override {
    while (auto frame = bag_->next()) {
      const auto why = gate_.check(frame->timestamp);
      if (!why) return frame;
      if (gate_.refused() <= kWarnings)
        spdlog::warn("bag '{}': frame {} dropped: its {} (trajectory.tum must be readable by `slambooster eval`)",
                     path_, frame->index, *why);
    }
    return std::nullopt;
  }

 private:
  static constexpr size_t kWarnings = 5;
  std::unique_ptr<FrameSource> bag_;
  std::string path_;
  StampGate gate_;
};

}  // namespace

std::unique_ptr<FrameSource> openBag(const std::string& path, const SequenceOptions& options) {
  const LoadedPlugin& p = plugin();
  if (!p.open) throw Error("opening '" + path + "': " + p.error);
  std::unique_ptr<FrameSource> bag(p.open(path, options));
  // The CameraInfo's size, intrinsics and depth scale under the bounds of every door (drivers/camera_bounds.h).
  checkCameraBounds("bag '" + path + "' (its CameraInfo)", bag->info().intrinsics, bag->info().depthScale);
  return std::make_unique<StampCheckedBag>(std::move(bag), path);
}

std::vector<odometry::OdometrySample> readBagOdometry(const std::string& path, const std::string& topic,
                                                     const std::string& cameraMount, std::string* source) {
  const LoadedPlugin& p = plugin();
  if (!p.odometry) throw Error("reading the odometry of '" + path + "': " + p.error);
  std::vector<odometry::OdometrySample> out;
  std::string from;
  p.odometry(path, topic, cameraMount, out, from);
  if (source) *source = from;
  return out;
}

}  // namespace sb
