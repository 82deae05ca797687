// The map store's directory (runtime/map_store.h): made or opened (every file checked), format.json, the state
// files and keyframes.bin, the summary. The volume's side is in runtime/map_store_volume.cpp, the slabs' worker
// in runtime/map_store_writer.cpp, the store in memory in runtime/map_store_memory.cpp.
#include "runtime/map_store.h"

#include <spdlog/spdlog.h>

#include <algorithm>
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
      keptStates_[file->name] = mapstore::stateFilePayload(path, mapstore::readFileBytes(path, file->what),
                                                           file->magic, file->what, file->version);
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

void MapStore::saveKeyframes(const KeyframeDatabase& keyframes) {
  if (!writing_ || inMemory()) return;
  const std::vector<const Keyframe*> all = keyframes.all();
  mapstore::writeFileBytes(dir_ + "/keyframes.bin", mapstore::encodeKeyframes(all));
  keyframesSaved_ = all.size();
}

const std::vector<uint8_t>* MapStore::keptState(const mapstore::StateFile& file) const {
  const auto it = keptStates_.find(file.name);
  return it == keptStates_.end() ? nullptr : &it->second.bytes;
}

uint32_t MapStore::keptStateVersion(const mapstore::StateFile& file) const {
  const auto it = keptStates_.find(file.name);
  return it == keptStates_.end() ? 0 : it->second.version;
}

void MapStore::saveState(const mapstore::StateFile& file, const std::vector<uint8_t>& payload) {
  if (!writing_ || inMemory() || payload.empty()) return;
  const std::vector<uint8_t> bytes = mapstore::encodeStateFile(file.magic, file.version, payload);
  mapstore::writeFileBytes(statePath(file), bytes);
  savedStates_[file.name] = bytes.size();
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
