#include "runtime/map_store.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <regex>

#include "core/atomic_file.h"
#include "core/config_reader.h"
#include "core/error.h"
#include "runtime/map_store_bytes.h"

namespace sb {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFormatName = "slambooster map store";
constexpr int16_t kUnobservedTsdf = 32767;  // kernels/volume.h: a cleared voxel is (+1, 0)

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void writeBytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  writeFileAtomically(path, [&](std::FILE* f, const std::string& temporary) {
    if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size())
      throw Error("map store: cannot write '" + temporary + "'");
  });
}

// The world voxel of a slab's first voxel (its corner is a whole number of voxels from the origin).
std::array<int, 3> worldVoxel(const Eigen::Vector3d& corner, double voxelSize) {
  std::array<int, 3> v{};
  for (int a = 0; a < 3; ++a) v[size_t(a)] = static_cast<int>(std::lround(corner[a] / voxelSize));
  return v;
}

}  // namespace

MapStore::MapStore(std::string dir, const PipelineConfig& config, const MapStoreOptions& options)
    : dir_(std::move(dir)), config_(config), options_(options) {
  if (!config.movesVolume())
    throw Error("--map-store needs the moving volume (volume_mode moving, the default of slambooster run); this run "
                "has a fixed volume (--fixed-volume or volume_mode fixed)");
  std::error_code ec;
  if (fs::exists(dir_ + "/format.json", ec)) {
    openExisting();
  } else {
    if (fs::exists(dir_, ec) && !fs::is_directory(dir_, ec))
      throw Error("map store: '" + dir_ + "' is not a directory; give a directory (created when absent)");
    if (fs::exists(dir_, ec) && !fs::is_empty(dir_, ec))
      throw Error("map store: '" + dir_ + "' holds files but no format.json: not a map store; give an empty or "
                  "absent directory, or the store itself");
    fs::create_directories(dir_ + "/slabs", ec);
    if (ec) throw Error("map store: cannot create '" + dir_ + "/slabs': " + ec.message());
    writeFormat();
  }
  writing_ = !kept();
  if (!slabs_.empty() && !kept())
    throw Error("map store: '" + dir_ + "' holds slabs but '" + dir_ + "/keyframes.bin' is missing or empty: the "
                "map cannot be localised in; restore keyframes.bin or give another --map-store");
}

MapStore::~MapStore() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  work_.notify_all();
  if (worker_.joinable()) worker_.join();
  if (error_) {
    try {
      std::rethrow_exception(error_);
    } catch (const std::exception& e) {
      spdlog::error("map store: {}", e.what());
    }
  }
}

void MapStore::writeFormat() const {
  const nlohmann::json f = {{"format", kFormatName},
                            {"version", mapstore::kFormatVersion},
                            {"voxel_size_m", config_.voxelSize()},
                            {"mu_m", config_.mu},
                            {"volume_resolution", config_.volumeResolution},
                            {"volume_size_m", config_.volumeSize}};
  writeFileAtomically(dir_ + "/format.json", [&](std::FILE* file, const std::string&) {
    const std::string text = f.dump(2) + "\n";
    std::fwrite(text.data(), 1, text.size(), file);
  });
}

void MapStore::openExisting() {
  const std::string formatPath = dir_ + "/format.json";
  const nlohmann::json f = readJsonConfig(formatPath, "map store format");
  if (f.value("format", std::string()) != kFormatName)
    throw Error("map store: '" + formatPath + "' does not name the format \"" + kFormatName +
                "\": not a map store; give another --map-store");
  if (!f.contains("version") || !f["version"].is_number_unsigned() || f["version"] != mapstore::kFormatVersion)
    throw Error("map store: '" + formatPath + "' is format version " +
                (f.contains("version") ? f["version"].dump() : "?") + ", this build reads " + std::to_string(mapstore::kFormatVersion) +
                ": use the slambooster that wrote it, or another --map-store");
  const auto same = [&](const char* key, double here) {
    if (!f.contains(key) || !f[key].is_number() || std::abs(f[key].get<double>() - here) > 1e-6 * std::abs(here))
      throw Error("map store: '" + formatPath + "' has " + key + " " + (f.contains(key) ? f[key].dump() : "missing") +
                  ", this run " + std::to_string(here) + ": run with the volume the store was made with "
                  "(volume_size_m / volume_resolution / mu), or give another --map-store");
  };
  same("voxel_size_m", config_.voxelSize());
  same("mu_m", config_.mu);
  const std::string keyframes = dir_ + "/keyframes.bin";
  std::error_code ec;
  if (fs::exists(keyframes, ec)) keptKeyframes_ = mapstore::readKeyframes(keyframes);
  for (const mapstore::StateFile* file : {&mapstore::kNavmapFile, &mapstore::kOdometryFile}) {
    const std::string path = statePath(*file);
    if (fs::exists(path, ec))
      keptStates_[file->name] =
          mapstore::stateFilePayload(path, mapstore::readFileBytes(path, file->what), file->magic, file->what);
  }
  static const std::regex slabName("slab-([0-9]{6,})\\.tsdf");
  if (!fs::is_directory(dir_ + "/slabs", ec))
    throw Error("map store: '" + dir_ + "/slabs' is missing: the store is incomplete; give another --map-store");
  for (const auto& e : fs::directory_iterator(dir_ + "/slabs")) {
    std::smatch m;
    const std::string name = e.path().filename().string();
    if (!std::regex_match(name, m, slabName)) continue;  // a temporary of a killed write: not part of the store
    Entry entry;
    entry.path = e.path().string();
    entry.number = std::stoul(m[1].str());
    entry.box = mapstore::readSlabHeader(entry.path);  // checks the whole file
    entry.size = fs::file_size(e.path());
    slabs_.push_back(entry);
  }
  std::sort(slabs_.begin(), slabs_.end(), [](const Entry& a, const Entry& b) { return a.number < b.number; });
  for (const Entry& e : slabs_) slabBytes_ += e.size;
  nextNumber_ = slabs_.empty() ? 0 : slabs_.back().number + 1;
}

void MapStore::localised(size_t frame, double timestamp) {
  if (writing_) return;
  writing_ = true;
  localisedFrame_ = frame;
  localisedStamp_ = timestamp;
  spdlog::info("map store: localised in '{}' at frame {}: poses are in its frame; mapping continues into it", dir_,
               frame);
}

void MapStore::loadBox(const mapstore::SlabBox& world, const VolumeWindow& window, BackendVolume& volume,
                       bool cleared) {
  const auto start = std::chrono::steady_clock::now();
  std::array<int, 3> first{};
  for (int a = 0; a < 3; ++a) first[size_t(a)] = world.first[a] - window.cornerVoxels()[a];
  std::vector<Entry> meeting;  // oldest first: a newer slab's voxels win where two overlap
  {
    std::lock_guard lock(mutex_);
    for (const Entry& e : slabs_)
      if (e.box.intersects(world)) meeting.push_back(e);
  }
  if (meeting.empty()) {
    loadMs_ += msSince(start);
    return;
  }
  std::vector<int16_t> box(2 * world.voxels());
  if (cleared) {
    for (size_t i = 0; i < box.size(); i += 2) box[i] = kUnobservedTsdf, box[i + 1] = 0;
  } else {
    volume.readVolumeBox(first, world.extent, box.data());
  }
  for (const Entry& e : meeting) {
    if (e.bytes)
      mapstore::mergeSlab(*e.bytes, e.path, world, box.data());
    else
      mapstore::mergeSlab(e.path, world, box.data());
  }
  volume.writeVolumeBox(first, world.extent, box.data());
  loadMs_ += msSince(start);
}

bool MapStore::placeFor(const Eigen::Isometry3d& pose, VolumeWindow& window, BackendVolume& volume) {
  if (placedCorner_ && *placedCorner_ == window.cornerVoxels() && window.shiftFor(pose, window.cornerVoxels()).isZero())
    return true;  // placed already
  if (placedThisFrame_) return false;
  placedThisFrame_ = true;
  if (volumeUnkept_) {
    keepVolume(window, volume);
    volumeUnkept_ = false;
  }
  drain();  // the slabs still queued (an in-run relocalisation's whole volume) are kept before the volume moves
  window.placeFor(pose, volume);
  if (placedCorner_ && *placedCorner_ == window.cornerVoxels()) return true;
  const int r = config_.volumeResolution;
  mapstore::SlabBox world;
  for (int a = 0; a < 3; ++a) world.first[size_t(a)] = window.cornerVoxels()[a];
  world.extent = {r, r, r};
  // Nothing is fused while localising: the volume holds the store's surface only (what stayed in it from an
  // earlier placement, the rest cleared by the move), so it is written whole from the store.
  loadBox(world, window, volume, /*cleared=*/true);
  placedCorner_ = window.cornerVoxels();
  ++placements_;
  return true;
}

void MapStore::swapIn(const std::array<int, 3>& first, const std::array<int, 3>& extent, const VolumeWindow& window,
                      BackendVolume& volume) {
  if (!writing_) return;
  // In memory, only once a relocalisation has placed the volume from the kept slabs: until then the run maps as
  // one without them (the same poses, byte for byte), and a revisit is tracked against what the volume holds.
  if (inMemory() && placements_ == 0) return;
  mapstore::SlabBox world;
  for (int a = 0; a < 3; ++a) world.first[size_t(a)] = first[size_t(a)] + window.cornerVoxels()[a];
  world.extent = extent;
  // A slab that left and meets the box is kept before the volume comes back over it. Only then: the slab that
  // left with this shift lies on the other side of the volume, and its encoding goes on beside the run.
  if (pendingMeets(world)) drain();
  loadBox(world, window, volume, /*cleared=*/false);
  ++swapIns_;
}

void MapStore::addSlab(std::shared_ptr<const VolumeSlab> slab) {
  if (!writing_ || !slab) return;
  std::unique_lock lock(mutex_);
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  const size_t bytes = slab->bytes();
  room_.wait(lock, [&] { return queuedBytes_ == 0 || queuedBytes_ + bytes <= options_.queueBytes; });
  queue_.push_back(std::move(slab));
  queuedBytes_ += bytes;
  ++pending_;
  if (!worker_.joinable()) worker_ = std::thread([this] { workerLoop(); });
  work_.notify_one();
}

bool MapStore::pendingMeets(const mapstore::SlabBox& world) const {
  const auto meets = [&](const VolumeSlab& slab) {
    mapstore::SlabBox box;
    box.first = worldVoxel(slab.corner, config_.voxelSize());
    box.extent = slab.extent;
    return box.intersects(world);
  };
  std::lock_guard lock(mutex_);
  if (writingNow_ && meets(*writingNow_)) return true;
  return std::any_of(queue_.begin(), queue_.end(), [&](const auto& slab) { return meets(*slab); });
}

void MapStore::drain() {
  std::unique_lock lock(mutex_);
  room_.wait(lock, [&] { return pending_ == 0; });
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

void MapStore::workerLoop() {
  for (;;) {
    std::shared_ptr<const VolumeSlab> slab;
    {
      std::unique_lock lock(mutex_);
      work_.wait(lock, [&] { return stop_ || !queue_.empty(); });
      if (queue_.empty()) return;
      slab = queue_.front();
      queue_.pop_front();
      writingNow_ = slab;
    }
    const auto start = std::chrono::steady_clock::now();
    try {
      writeSlab(*slab);
    } catch (...) {
      std::lock_guard lock(mutex_);
      if (!error_) error_ = std::current_exception();
    }
    std::lock_guard lock(mutex_);
    writingNow_.reset();
    workerMs_ += msSince(start);
    queuedBytes_ -= slab->bytes();
    --pending_;
    room_.notify_all();
  }
}

void MapStore::writeSlab(const VolumeSlab& slab) {
  mapstore::SlabBox box;
  box.first = worldVoxel(slab.corner, config_.voxelSize());
  box.extent = slab.extent;
  const std::vector<uint8_t> bytes = mapstore::encodeSlab(box, slab.voxels.data());
  if (bytes.empty()) return;  // nothing observed: nothing to keep
  size_t number;
  {
    std::lock_guard lock(mutex_);
    number = nextNumber_++;
  }
  char name[32];
  std::snprintf(name, sizeof name, "slab-%06zu.tsdf", number);
  if (inMemory()) {
    keepSlab(box, bytes, number, name);
    return;
  }
  const std::string path = dir_ + "/slabs/" + name;
  writeBytes(path, bytes);
  std::lock_guard lock(mutex_);
  slabs_.push_back({path, nullptr, number, box, bytes.size()});
  slabBytes_ += bytes.size();
  enforceRetentionLocked();
}

void MapStore::enforceRetentionLocked() {
  while (options_.keepSlabBytes > 0 && slabBytes_ > options_.keepSlabBytes && slabs_.size() > 1) {
    const Entry oldest = slabs_.front();
    std::error_code ec;
    if (!oldest.bytes) fs::remove(oldest.path, ec);
    if (ec) {
      spdlog::warn("map store: cannot remove '{}' for the bound of {} MiB: {}", oldest.path,
                   options_.keepSlabBytes >> 20, ec.message());
      return;
    }
    if (oldest.bytes && removedFiles_ == 0)
      spdlog::info("map store: dropped the oldest kept slab ({} bytes), and from now on the oldest as needed: the "
                   "slabs kept in memory are bounded to {} MiB (relocalise_kept_map_mib)",
                   oldest.size, options_.keepSlabBytes >> 20);
    else if (!oldest.bytes)
      spdlog::info("map store: removed the oldest slab '{}' ({} bytes): the store's slabs are bounded to {} MiB",
                   oldest.path, oldest.size, options_.keepSlabBytes >> 20);
    slabs_.erase(slabs_.begin());
    slabBytes_ -= oldest.size;
    ++removedFiles_;
    removedBytes_ += oldest.size;
  }
}

void MapStore::saveKeyframes(const KeyframeDatabase& keyframes) {
  if (!writing_ || inMemory()) return;
  const std::vector<const Keyframe*> all = keyframes.all();
  writeBytes(dir_ + "/keyframes.bin", mapstore::encodeKeyframes(all));
  keyframesSaved_ = all.size();
}

const std::vector<uint8_t>* MapStore::keptState(const mapstore::StateFile& file) const {
  const auto it = keptStates_.find(file.name);
  return it == keptStates_.end() ? nullptr : &it->second;
}

void MapStore::saveState(const mapstore::StateFile& file, const std::vector<uint8_t>& payload) {
  if (!writing_ || inMemory() || payload.empty()) return;
  const std::vector<uint8_t> bytes = mapstore::encodeStateFile(file.magic, payload);
  writeBytes(statePath(file), bytes);
  savedStates_[file.name] = bytes.size();
}

void MapStore::keepVolume(const VolumeWindow& window, BackendVolume& volume) {
  if (!writing_) return;
  const int r = config_.volumeResolution;
  auto slab = std::make_shared<VolumeSlab>();
  slab->resolution = r;
  slab->extent = {r, r, r};
  slab->voxels.resize(2 * size_t(r) * size_t(r) * size_t(r));
  volume.readVolumeBox(slab->first, slab->extent, slab->voxels.data());
  slab->corner = window.cornerMetres();
  slab->voxelSize = config_.voxelSize();
  addSlab(std::move(slab));
  placedCorner_ = window.cornerVoxels();
  ++volumesKept_;
}

void MapStore::recoveryStarted(const VolumeWindow& window) {
  if (!writing_) return;
  placedCorner_ = window.cornerVoxels();
  volumeUnkept_ = true;
}

void MapStore::finish(const VolumeWindow& window, BackendVolume& volume, const KeyframeDatabase& keyframes) {
  if (!writing_ || inMemory()) return;  // in memory: kept for this run only
  keepVolume(window, volume);
  drain();
  saveKeyframes(keyframes);
}

nlohmann::json MapStore::summaryJson() const {
  std::lock_guard lock(mutex_);
  if (inMemory()) return inMemorySummaryLocked();
  nlohmann::json j = {{"dir", dir_},
                      {"kept", kept()},
                      {"kept_keyframes", keptKeyframes_.size()},
                      {"writing", writing_},
                      {"slab_files", slabs_.size()},
                      {"slab_bytes", slabBytes_},
                      {"slab_files_removed", removedFiles_},
                      {"keyframes_saved", keyframesSaved_},
                      {"state_files_kept", nlohmann::json::array()},
                      {"state_files_saved", savedStates_},
                      {"placements", placements_},
                      {"swap_ins", swapIns_},
                      {"load_ms", loadMs_},
                      {"worker_ms", workerMs_}};
  for (const auto& [name, payload] : keptStates_) j["state_files_kept"].push_back(name);
  j["localised_frame"] = localisedFrame_ ? nlohmann::json(*localisedFrame_) : nlohmann::json(nullptr);
  j["localised_s"] = localisedFrame_ ? nlohmann::json(localisedStamp_) : nlohmann::json(nullptr);
  return j;
}

}  // namespace sb
