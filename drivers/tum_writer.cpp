#include "drivers/tum_writer.h"

#include <spdlog/spdlog.h>

#include <cstdio>
#include <filesystem>

#include "core/error.h"
#include "core/png_io.h"
#include "drivers/calibration.h"
#include "drivers/tum_layout.h"

namespace fs = std::filesystem;

namespace sb {

namespace {

// depth.txt timestamps: seconds with microsecond resolution (the TUM convention).
std::string formatTimestamp(double seconds) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", seconds);
  return buf;
}

std::string depthFileName(size_t frame) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%s/%06zu.png", tum::kDepthDir, frame);
  return buf;
}

}  // namespace

TumSequenceWriter::TumSequenceWriter(const std::string& directory, const SequenceInfo& info, bool overwrite)
    : directory_(directory), info_(info) {
  const fs::path dir(directory);
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec))
      throw Error("cannot write sequence to '" + directory + "': it exists and is not a directory");
    if (!fs::is_empty(dir, ec)) {
      if (!overwrite)
        throw Error("cannot write sequence to '" + directory +
                    "': the directory is not empty; choose another or allow overwriting");
      // The files this writer produces: `overwrite` removes exactly these, nothing else in the directory.
      for (const char* name : {tum::kIndexFile, tum::kCalibrationFile, tum::kGroundTruthFile})
        fs::remove(dir / name, ec);
      fs::remove_all(dir / tum::kDepthDir, ec);
    }
  }
  fs::create_directories(dir / tum::kDepthDir, ec);
  if (ec) throw Error("cannot create '" + (dir / tum::kDepthDir).string() + "': " + ec.message());
  if (info.intrinsics.width <= 0 || info.intrinsics.height <= 0)
    throw Error("cannot write sequence to '" + directory + "': intrinsics give an empty image size");
  if (!(info.depthScale > 0))
    throw Error("cannot write sequence to '" + directory + "': depth scale must be > 0");

  const std::string indexPath = (dir / tum::kIndexFile).string();
  index_.open(indexPath);
  if (!index_) throw Error("cannot write '" + indexPath + "': check that the directory is writable");
  index_ << "# timestamp filename (depth: 16-bit PNG, " << info.depthScale << " units per metre)\n";
}

TumSequenceWriter::~TumSequenceWriter() {
  if (finished_) return;
  try {
    finish();
  } catch (const std::exception& e) {
    spdlog::error("finishing sequence '{}' failed: {}", directory_, e.what());
  }
}

void TumSequenceWriter::write(const DepthFrame& frame) {
  if (finished_) throw Error("sequence '" + directory_ + "': write() after finish()");
  if (frame.depth.width() != info_.intrinsics.width || frame.depth.height() != info_.intrinsics.height)
    throw Error("sequence '" + directory_ + "', frame " + std::to_string(frames_) + ": depth image is " +
                std::to_string(frame.depth.width()) + "x" + std::to_string(frame.depth.height()) +
                " but the sequence is " + std::to_string(info_.intrinsics.width) + "x" +
                std::to_string(info_.intrinsics.height));
  // Compare what the reader will see: timestamps rounded to the written resolution must increase.
  const std::string stamp = formatTimestamp(frame.timestamp);
  const double written = std::stod(stamp);
  if (!(written > lastTimestamp_))
    throw Error("sequence '" + directory_ + "', frame " + std::to_string(frames_) + ": timestamp " + stamp +
                " s does not increase (previous " + formatTimestamp(lastTimestamp_) +
                " s at microsecond resolution)");
  const std::string name = depthFileName(frames_);
  writePng16((fs::path(directory_) / name).string(), frame.depth);
  index_ << stamp << ' ' << name << '\n';
  if (!index_) throw Error("writing '" + directory_ + "/" + tum::kIndexFile + "' failed (disk full?)");
  lastTimestamp_ = written;
  ++frames_;
}

void TumSequenceWriter::writeGroundTruth(const Trajectory& trajectory) {
  writeTumTrajectory((fs::path(directory_) / tum::kGroundTruthFile).string(), trajectory,
                     "reference poses of this sequence");
}

void TumSequenceWriter::finish() {
  if (finished_) return;
  finished_ = true;
  index_.flush();
  const bool ok = static_cast<bool>(index_);
  index_.close();
  if (!ok) throw Error("writing '" + directory_ + "/" + tum::kIndexFile + "' failed (disk full?)");
  writeCalibration((fs::path(directory_) / tum::kCalibrationFile).string(), info_);
}

}  // namespace sb
