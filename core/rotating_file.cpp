#include "core/rotating_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>

#include "core/disk_full.h"
#include "core/error.h"
#include "core/exclusive_file.h"

namespace sb {

namespace {

// "frames.jsonl" -> ("frames", ".jsonl"); "power.csv" -> ("power", ".csv"); no dot: no extension.
std::pair<std::string, std::string> splitName(const std::string& name) {
  const size_t dot = name.find('.');
  if (dot == std::string::npos || dot == 0) return {name, ""};
  return {name.substr(0, dot), name.substr(dot)};
}

// The segment number of `file` in stream (stem, ext), or 0 when it is not one of its segments.
uint64_t segmentNumber(const std::string& file, const std::string& stem, const std::string& ext) {
  const std::string prefix = stem + "-";
  if (file.size() <= prefix.size() + ext.size() || file.compare(0, prefix.size(), prefix) != 0 ||
      file.compare(file.size() - ext.size(), ext.size(), ext) != 0)
    return 0;
  const std::string digits = file.substr(prefix.size(), file.size() - prefix.size() - ext.size());
  if (digits.empty() || digits.size() > 18 || digits.find_first_not_of("0123456789") != std::string::npos)
    return 0;
  return std::stoull(digits);
}

// number -> path of the stream's segments in `dir`.
std::map<uint64_t, std::string> segmentsIn(const std::string& dir, const std::string& stem,
                                           const std::string& ext) {
  std::map<uint64_t, std::string> found;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const uint64_t n = segmentNumber(entry.path().filename().string(), stem, ext);
    if (n > 0) found[n] = entry.path().string();
  }
  return found;
}

int64_t modifiedNs(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return 0;
  return static_cast<int64_t>(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
}

}  // namespace

std::string segmentName(const std::string& name, uint64_t segment) {
  const auto [stem, ext] = splitName(name);
  char number[32];
  std::snprintf(number, sizeof number, "%06llu", static_cast<unsigned long long>(segment));
  return stem + "-" + number + ext;
}

std::vector<std::string> streamFiles(const std::string& dir, const std::string& name) {
  const auto [stem, ext] = splitName(name);
  std::vector<std::string> files;
  for (const auto& [n, path] : segmentsIn(dir, stem, ext)) files.push_back(path);
  if (files.empty()) {
    const std::string single = (std::filesystem::path(dir) / name).string();
    if (std::filesystem::exists(single)) files.push_back(single);
  }
  return files;
}

RotatingFile::RotatingFile(const std::string& dir, const std::string& name, std::string what,
                           std::string header, std::shared_ptr<SegmentStore> store)
    : dir_(dir), what_(std::move(what)), header_(std::move(header)), store_(std::move(store)) {
  std::tie(stem_, ext_) = splitName(name);
  if (!store_) {
    path_ = (std::filesystem::path(dir_) / name).string();
  } else {
    // Segments of an earlier run stay (and count against the limits); this run numbers on after them.
    for (const auto& [n, path] : segmentsIn(dir_, stem_, ext_)) {
      std::error_code ec;
      const auto bytes = std::filesystem::file_size(path, ec);
      store_->addClosed(path, ec ? 0 : static_cast<uint64_t>(bytes), modifiedNs(path));
      segment_ = std::max(segment_, n);
    }
  }
  openSegment();
  firstSegment_ = segment_;
}

std::vector<std::string> RotatingFile::files() const {
  if (!store_) return {path_};
  std::vector<std::string> out;
  for (uint64_t n = firstSegment_; n <= segment_; ++n) {
    const std::string path = (std::filesystem::path(dir_) / segmentName(stem_ + ext_, n)).string();
    if (std::filesystem::exists(path)) out.push_back(path);
  }
  return out;
}

RotatingFile::~RotatingFile() {
  if (!store_) return;
  try {
    store_->dropCurrent(this);
    store_->addClosed(path_, static_cast<uint64_t>(size_), SegmentStore::nowOrder());
  } catch (...) {  // a destructor never throws; the segment then stays on disk outside the limits
  }
}

void RotatingFile::openSegment() {
  if (store_) path_ = (std::filesystem::path(dir_) / segmentName(stem_ + ext_, ++segment_)).string();
  try {
    fd_ = createReplacing(path_);  // a symlink or hard link of that name is replaced, never written through
  } catch (const Error& e) {
    throw WriteError("cannot write " + what_ + ": " + e.what(), path_);
  }
  size_ = 0;
  opened_ = std::chrono::steady_clock::now();
  if (store_) store_->reserve(this, header_.size());  // room first: the limits hold while it is written
  if (!header_.empty()) write(header_);
  if (store_) store_->setCurrent(this, static_cast<uint64_t>(size_));
}

void RotatingFile::rotate() {
  const std::string closedPath = path_;
  const uint64_t closedBytes = static_cast<uint64_t>(size_);
  fd_.reset();
  store_->dropCurrent(this);
  store_->addClosed(closedPath, closedBytes, SegmentStore::nowOrder());
  openSegment();
}

bool RotatingFile::due() const {
  if (!store_ || static_cast<size_t>(size_) <= header_.size()) return false;  // never an empty segment
  const RetentionLimits& l = store_->limits();
  if (static_cast<uint64_t>(size_) >= l.segmentBytes) return true;
  return l.segmentSeconds > 0 &&
         std::chrono::steady_clock::now() - opened_ >= std::chrono::duration<double>(l.segmentSeconds);
}

void RotatingFile::append(std::string_view lines) {
  if (due()) rotate();
  if (store_) store_->reserve(this, static_cast<uint64_t>(size_) + lines.size());
  write(lines);
  if (store_) {
    store_->setCurrent(this, static_cast<uint64_t>(size_));
    store_->enforce();
  }
}

void RotatingFile::write(std::string_view data) {
  bool rotatedForSpace = false;
  while (true) {
    const int error = writeOnce(data);
    if (error == 0) return;
    if (store_ && (error == ENOSPC || error == EDQUOT)) {
      // Oldest first: closed segments of any stream; as a last resort this stream's current segment.
      if (store_->removeOldest()) {
        ++spaceRecoveries_;
        continue;
      }
      if (!rotatedForSpace && static_cast<size_t>(size_) > header_.size()) {
        rotatedForSpace = true;
        rotate();
        continue;
      }
    }
    throwWriteFailure("writing " + what_ + " '" + path_ + "' failed: " + std::strerror(error) +
                          "; the file keeps the lines before it (free disk space" +
                          (store_ ? ", or lower output.rotation.keep_mib" : "") + ", and run again)",
                      path_, error);
  }
}

int RotatingFile::writeOnce(std::string_view data) {
  size_t done = 0;
  while (done < data.size()) {
    const ssize_t n =
        ::pwrite(fd_.get(), data.data() + done, data.size() - done, size_ + static_cast<off_t>(done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error = n < 0 ? errno : ENOSPC;
      (void)!::ftruncate(fd_.get(), size_);  // drop the part line: the file stays whole lines
      return error;
    }
    done += static_cast<size_t>(n);
  }
  size_ += static_cast<off_t>(done);
  return 0;
}

void RotatingFile::sync() {
  if (::fsync(fd_.get()) != 0) {
    const int error = errno;
    throwWriteFailure("cannot sync " + what_ + " '" + path_ + "' to disk: " + std::strerror(error), path_,
                      error);
  }
}

}  // namespace sb
