#include "runtime/map_slabs.h"

#include <spdlog/spdlog.h>
#include <fcntl.h>
#include <sys/resource.h>
#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/error.h"
#include "core/exclusive_file.h"
#include "mesh/mesh_pieces.h"
#include "mesh/ply_merge.h"
#include "mesh/ply_writer.h"
#include "runtime/run.h"

namespace sb {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

constexpr int kWorkerNice = 10;  // the worker's nice above the SLAM thread's
constexpr const char* kPrefix = "slab-";
constexpr const char* kSuffix = ".ply";
constexpr const char* kFolder = "map_slabs";  // inside the run's directory, never a symlink (issue 44 S2)
// A slab's write takes its file's size and at most this more on disk (PlyPieceWriter's 64 KiB chunk, the
// header, the file system's blocks of its three files): MapSlabs::write makes room for the largest slab so
// far plus this before each write.
constexpr uint64_t kSlabWriteMarginBytes = 1ull << 20;

// The number of a slab file's name (slab-NNNNNN.ply), 0 for any other name.
size_t slabNumber(const std::string& name) {
  const std::string prefix = kPrefix, suffix = kSuffix;
  if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
    return 0;
  const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }) ||
      digits.size() > 18)
    return 0;
  return std::stoull(digits);
}

}  // namespace

// glibc keeps what a thread frees in that thread's arena, resident: after a slab (a 20 MiB copy and its
// mesh, on this thread) the process held 55 MiB more for the rest of the run on the corridor drive
// (docs/moving-volume.md). Hands the free pages back to the system (a few ms per slab, on the worker).
static void releaseFreedMemory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

// glibc raises its mmap threshold to the size of the largest mapped block freed (up to 32 MiB): once a slab's
// copy (20 MiB) is freed, every buffer under that size (the final volume's mesh at the end, 15 MB on the
// drive) comes from the arenas instead, where it fragments and stays resident (+20 MiB for the rest of the
// run and +35 MiB at the end, against +17 MiB in a fixed run). A fixed threshold, set once by the first run
// with a map, keeps such buffers mapped, given back when freed; smaller ones (a frame's) stay in the arenas.
constexpr int kMmapThresholdBytes = 4 << 20;

static void fixMmapThreshold() {
#if defined(__GLIBC__)
  static std::once_flag once;
  std::call_once(once, [] { mallopt(M_MMAP_THRESHOLD, kMmapThresholdBytes); });
#endif
}

MapSlabs::MapSlabs(std::string dir, const Options& options) : dir_(std::move(dir)), options_(options) {
  fixMmapThreshold();
  listEarlier();
  if (options_.store) options_.store->attach(this);
}

MapSlabs::~MapSlabs() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  work_.notify_all();
  if (worker_.joinable()) worker_.join();  // the worker writes what is queued before it stops
  if (options_.store) options_.store->detach(this);
  if (error_) {
    try {
      std::rethrow_exception(error_);
    } catch (const std::exception& e) {
      spdlog::error("map slabs: {}", e.what());
    }
  }
}

void MapSlabs::rethrowLocked() {
  if (!error_) return;
  std::exception_ptr error = error_;
  error_ = nullptr;  // thrown once
  std::rethrow_exception(error);
}

void MapSlabs::add(std::shared_ptr<const VolumeSlab> slab) {
  std::unique_lock lock(mutex_);
  rethrowLocked();
  const size_t bytes = slab->bytes();
  const auto fits = [&] { return pending_ == 0 || queuedBytes_ + bytes <= options_.queueBytes; };
  if (!fits()) {  // back-pressure: the SLAM thread waits for the worker rather than dropping a slab
    const auto start = Clock::now();
    room_.wait(lock, fits);
    stats_.waitMs += msSince(start);
    ++stats_.waits;
  }
  queuedBytes_ += bytes;
  ++pending_;
  stats_.peakQueuedBytes = std::max(stats_.peakQueuedBytes, queuedBytes_);
  queue_.push_back(std::move(slab));
  if (!worker_.joinable()) worker_ = std::thread([this] { workerLoop(); });
  work_.notify_one();
}

void MapSlabs::check() {
  std::lock_guard lock(mutex_);
  rethrowLocked();
}

void MapSlabs::drain() {
  std::unique_lock lock(mutex_);
  room_.wait(lock, [&] { return pending_ == 0; });
  rethrowLocked();
}

void MapSlabs::workerLoop() {
  // Below the SLAM thread and its pool (nice + kWorkerNice, this thread only: Linux's nice is per thread), so
  // that where they fill the cores the slabs take the idle time; when the queue fills, the SLAM thread waits.
  errno = 0;
  const int nice = getpriority(PRIO_PROCESS, 0);
  if (errno == 0)
    setpriority(PRIO_PROCESS, 0, std::min(nice + kWorkerNice, 19));  // best effort: any failure keeps it
  ThreadPool serial(1);  // this thread alone: the global pool is the SLAM thread's (same mesh for any count)
  std::unique_lock lock(mutex_);
  for (;;) {
    work_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    if (queue_.empty()) return;  // stopped, and every slab written
    std::shared_ptr<const VolumeSlab> slab = std::move(queue_.front());
    queue_.pop_front();
    const size_t bytes = slab->bytes();
    lock.unlock();
    const auto start = Clock::now();
    std::exception_ptr failure;
    try {
      write(*slab, serial);
    } catch (...) {
      failure = std::current_exception();
    }
    slab.reset();  // its memory goes back (unless the navigation map still votes it) before the room is counted
    releaseFreedMemory();
    lock.lock();
    stats_.workerMs += msSince(start);
    if (failure && !error_) error_ = failure;
    queuedBytes_ -= bytes;
    --pending_;
    room_.notify_all();
  }
}

void MapSlabs::listEarlier() {
  // Slab files of an earlier start: in the retention (oldest first), not in this run's map; numbered on
  // after.
  const std::filesystem::path folder = std::filesystem::path(dir_) / "map_slabs";
  std::error_code ec;
  if (!std::filesystem::exists(std::filesystem::symlink_status(folder, ec))) return;
  // A symlink (to a directory elsewhere) is refused: slabs are written and removed only inside dir_.
  folder_ = openOwnSubdirectory(openDirectory(dir_).get(), dir_, kFolder);
  std::vector<std::pair<size_t, Written>> earlier;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    const size_t number = slabNumber(entry.path().filename().string());
    std::error_code sizeError;
    const uint64_t bytes = entry.is_regular_file(sizeError) ? entry.file_size(sizeError) : 0;
    if (number > 0 && !sizeError)
      earlier.push_back({number, Written{entry.path().string(), bytes, false,
                                         SegmentStore::modifiedOrder(entry.path().string())}});
  }
  if (ec) throw Error("cannot list '" + folder.string() + "': " + ec.message() + " (check its permissions)");
  std::sort(earlier.begin(), earlier.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& [number, file] : earlier) {
    firstNumber_ = number;
    writtenBytes_ += file.bytes;
    written_.push_back(std::move(file));
  }
}

void MapSlabs::openFolder() {
  // Opened once, never through a symlink: every slab written or removed later is in this directory.
  const std::filesystem::path folder = std::filesystem::path(dir_) / kFolder;
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) throw Error("cannot create '" + folder.string() + "': " + ec.message());
  folder_ = openOwnSubdirectory(openDirectory(dir_).get(), dir_, kFolder);
}

void MapSlabs::write(const VolumeSlab& slab, ThreadPool& serial) {
  if (!folder_.valid()) openFolder();
  // The copy of the slab (no offset: VolumeView::boxOnly); the same mesh as the box read in place.
  VolumeView view;
  view.data = slab.voxels.data();
  view.resolution = slab.resolution;
  view.size = slab.voxelSize * static_cast<float>(slab.resolution);
  view.extent = slab.extent;
  view.boxOnly = true;
  char name[40];
  std::snprintf(name, sizeof name, "%s%06zu%s", kPrefix, firstNumber_ + slab.shift, kSuffix);
  const std::string folderPath = (std::filesystem::path(dir_) / kFolder).string();
  const std::string path = (std::filesystem::path(folderPath) / name).string();
  const Eigen::Isometry3f toWorld(Eigen::Translation3f(slab.corner.cast<float>()));
  // Streamed: each piece of the mesh goes to the file as it is extracted (the mesh is never held whole); the
  // file's bytes are writePly's of the whole mesh.
  size_t triangles = 0;
  const auto writeFile = [&] {
    PlyPieceWriter ply(folder_.get(), folderPath, name);  // new temporaries, renamed to `name` when whole
    extractMeshPieces(view, MeshOptions{}, serial, [&](Mesh& piece) {
      transformMesh(piece, toWorld);
      ply.add(piece);
    });
    triangles = ply.triangles();
    if (triangles > 0) ply.finish();
  };
  if (options_.store) {
    // Room before the write (issue 44 M3): at its peak a slab takes its file's size plus a chunk
    // (PlyPieceWriter puts the file together from its end, cutting the files aside as it goes; issue 53
    // finding 8: it took twice the file before), so the store frees the largest slab so far plus a margin
    // first; a full disk during the write (a larger slab than any before) still removes the oldest and writes
    // again.
    options_.store->makeRoom(largestSlabBytes_ + kSlabWriteMarginBytes);
    options_.store->writeMakingRoom(writeFile);  // a full disk: the oldest slab or segment goes, then again
  } else {
    writeFile();
  }
  if (triangles == 0) return;  // nothing observed left (e.g. the space behind the first view)
  std::error_code ec;
  const uint64_t bytes = std::filesystem::file_size(path, ec);
  {
    std::lock_guard lock(mutex_);
    written_.push_back(Written{path, ec ? 0 : bytes, true, SegmentStore::nowOrder()});
    largestSlabBytes_ = std::max(largestSlabBytes_, written_.back().bytes);
    writtenBytes_ += written_.back().bytes;
    triangles_ += triangles;
    enforceRetentionLocked();
  }
  if (options_.store) options_.store->enforce();  // the free-space floor (without this lock: it calls back)
}

std::optional<int64_t> MapSlabs::oldestRemovable() const {
  std::lock_guard lock(mutex_);
  if (written_.size() < 2) return std::nullopt;  // the newest slab always stays
  return written_.front().order;
}

uint64_t MapSlabs::removeOldestAttached() {
  std::lock_guard lock(mutex_);
  if (written_.size() < 2) return 0;
  const uint64_t bytes = written_.front().bytes;
  const std::string path = written_.front().path;
  const int error = removeSlabFile(path);  // already gone (removed by hand): forgotten all the same
  if (error) spdlog::warn("map slabs: cannot remove '{}' to make room: {}", path, std::strerror(error));
  removeOldestLocked();
  ++stats_.removedForSpace;
  return bytes;
}

void MapSlabs::removeOldestLocked() {
  const Written& oldest = written_.front();
  writtenBytes_ -= oldest.bytes;
  ++stats_.removedFiles;
  stats_.removedBytes += oldest.bytes;
  written_.pop_front();
}

int MapSlabs::removeSlabFile(const std::string& path) const {
  // Through the folder's descriptor: a map_slabs swapped for a symlink meanwhile is never followed.
  const std::string name = std::filesystem::path(path).filename().string();
  if (!folder_.valid() || ::unlinkat(folder_.get(), name.c_str(), 0) == 0 || errno == ENOENT) return 0;
  return errno;
}

void MapSlabs::enforceRetentionLocked() {
  if (options_.keepBytes == 0) return;
  while (writtenBytes_ > options_.keepBytes && written_.size() > 1) {
    const Written& oldest = written_.front();
    if (const int error = removeSlabFile(oldest.path))
      throw Error("cannot remove the old slab '" + oldest.path + "' (map_slabs retention): " +
                  std::strerror(error));
    removeOldestLocked();
  }
}

const std::vector<std::string>& MapSlabs::files() {
  drain();
  std::lock_guard lock(mutex_);
  files_.clear();
  for (const Written& w : written_)
    if (w.thisRun) files_.push_back(w.path);
  return files_;
}

size_t MapSlabs::triangles() {
  drain();
  std::lock_guard lock(mutex_);
  return triangles_;
}

MapSlabsStats MapSlabs::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

size_t MapSlabs::writeMap(const std::string& path, const Mesh& finalVolume) {
  return writeMergedPly(path, files(), finalVolume);
}

MapSlabFiles mapSlabFiles(const std::string& dir) {
  MapSlabFiles out;
  std::error_code ec;
  if (std::filesystem::is_symlink(std::filesystem::path(dir) / kFolder, ec)) return out;  // not ours
  for (const auto& entry :
       std::filesystem::directory_iterator(std::filesystem::path(dir) / "map_slabs", ec)) {
    std::error_code sizeError;
    if (slabNumber(entry.path().filename().string()) == 0 || !entry.is_regular_file(sizeError)) continue;
    const uintmax_t bytes = entry.file_size(sizeError);
    if (sizeError) continue;  // removed meanwhile
    out.bytes += bytes;
    ++out.files;
  }
  return out;
}

void writeRunMesh(const std::string& path, Pipeline& pipeline, MapSlabs* slabs, ThreadPool& pool,
                  SummarySink& summary) {
  if (slabs) slabs->drain();  // every slab on disk before the map is merged (throws a slab's failure)
  const PipelineConfig& config = pipeline.config();
  VolumeView view{pipeline.volumeData(), config.volumeResolution, config.volumeSize};
  const VolumeWindow* window = pipeline.volumeWindow();
  if (window) view.offset = window->offset();
  Mesh mesh = extractMesh(view, MeshOptions{}, pool);
  if (window && !window->cornerVoxels().isZero())  // to the world frame (a volume that never moved is in it)
    transformMesh(mesh, Eigen::Isometry3f(Eigen::Translation3f(window->cornerMetres().cast<float>())));
  if (slabs && !slabs->files().empty()) {
    summary.header().meshTriangles = slabs->writeMap(path, mesh);
    summary.header().meshSlabs = slabs->files().size();
  } else {
    writePly(path, mesh);  // whole or not at all (temporary file + rename)
    summary.header().meshTriangles = mesh.triangles.size();
  }
}

MovingVolumeSummary movingVolumeSummary(const VolumeWindow& window, const MapSlabs* slabs) {
  const VolumeWindowStats& s = window.stats();
  const Eigen::Vector3d corner = window.cornerMetres();
  MovingVolumeSummary v;
  v.shifts = s.shifts;
  v.shiftMs = s.shiftMs;
  v.slabMs = s.slabMs;
  v.cornerM = {corner.x(), corner.y(), corner.z()};
  if (slabs) {
    const MapSlabsStats m = slabs->stats();
    v.slabWorkerMs = m.workerMs;
    v.slabWaitMs = m.waitMs;
    v.slabQueuePeakMib = double(m.peakQueuedBytes) / double(1 << 20);
    v.slabFilesRemoved = m.removedFiles;
  }
  return v;
}

Eigen::Isometry3d movingVolumeOverview(Pipeline& pipeline) {
  Eigen::Isometry3d pose = overviewPose(pipeline.config());
  if (const VolumeWindow* window = pipeline.volumeWindow()) pose.pretranslate(window->cornerMetres());
  return pose;
}

}  // namespace sb
