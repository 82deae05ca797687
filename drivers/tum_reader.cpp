#include "drivers/tum_reader.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <utility>

#include "core/image.h"
#include "core/error.h"
#include "core/input_file.h"
#include "core/png_io.h"
#include "drivers/calibration.h"
#include "drivers/tum_index.h"
#include "drivers/tum_layout.h"

namespace fs = std::filesystem;

namespace sb {

namespace {

const char* const kIclGroundTruthExtension = ".freiburg";  // ICL-NUIM: livingRoom0n.gt.freiburg

// TUM RGB-D (Freiburg) defaults: fx = fy = 525, centre (319.5, 239.5), 5000 units per metre.
CameraDefaults tumDefaults() {
  CameraDefaults d;
  d.name = "TUM RGB-D (fx=fy=525, cx=319.5, cy=239.5, 5000 units/m)";
  d.intrinsics.fx = 525.f;
  d.intrinsics.fy = 525.f;
  d.intrinsics.cx = 319.5f;
  d.intrinsics.cy = 239.5f;
  d.depthScale = 5000.0;
  return d;
}

// 7-Scenes (Kinect v1 as recorded there): fx = fy = 585, centre (320, 240), millimetres.
CameraDefaults sevenScenesDefaults() {
  CameraDefaults d;
  d.name = "7-Scenes (fx=fy=585, cx=320, cy=240, 1000 units/m)";
  d.intrinsics.fx = 585.f;
  d.intrinsics.fy = 585.f;
  d.intrinsics.cx = 320.f;
  d.intrinsics.cy = 240.f;
  d.depthScale = 1000.0;
  return d;
}

// Largest image side accepted before decoding, pixels (guards allocations against corrupt headers).
constexpr uint32_t kMaxSide = kMaxDepthImageSide;
constexpr size_t kPngSignatureBytes = 8;
constexpr size_t kIhdrSizeOffset = 16;  // signature, chunk length, "IHDR"
constexpr size_t kIhdrSizeEnd = kIhdrSizeOffset + 8;

// Width and height from a PNG's IHDR chunk without decoding; nullopt when the file is not a readable PNG
// (readPng16 then reports what is wrong).
std::optional<std::pair<uint32_t, uint32_t>> pngSize(const std::string& path) {
  if (!isReadableRegularFile(path)) return std::nullopt;
  InputFile in(path, "depth image");
  unsigned char b[kIhdrSizeEnd];
  if (!in.read(reinterpret_cast<char*>(b), sizeof b)) return std::nullopt;
  if (std::string(reinterpret_cast<char*>(b) + kPngSignatureBytes + 4, 4) != "IHDR") return std::nullopt;
  const auto be32 = [](const unsigned char* p) {
    return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
  };
  return std::make_pair(be32(b + kIhdrSizeOffset), be32(b + kIhdrSizeOffset + 4));
}

// ICL-NUIM (living room / office, as SLAMBench uses it): fx = 481.2, fy = 480, centre (319.5, 239.5), 5000
// units per metre.
CameraDefaults iclNuimDefaults() {
  CameraDefaults d;
  d.name = "ICL-NUIM (fx=481.2, fy=480, cx=319.5, cy=239.5, 5000 units/m)";
  d.intrinsics.fx = 481.2f;
  d.intrinsics.fy = 480.f;
  d.intrinsics.cx = 319.5f;
  d.intrinsics.cy = 239.5f;
  d.depthScale = 5000.0;
  return d;
}

std::string where(const std::string& indexPath, size_t line) {
  return "'" + indexPath + "' line " + std::to_string(line);
}

}  // namespace

TumReader::TumReader(const std::string& directory, const SequenceOptions& options) {
  const fs::path dir(directory);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    const std::string problem = pathProblem(directory);
    throw Error("sequence directory " + quoteForMessage(directory) + " " +
                (problem.empty() ? std::string("is a file, not a directory") : problem));
  }
  indexPath_ = (dir / tum::kIndexFile).string();
  const std::string indexProblem = pathProblem(indexPath_);
  const bool associations = !indexProblem.empty() && isReadableRegularFile((dir / tum::kAssociationsFile).string());
  if (associations) indexPath_ = (dir / tum::kAssociationsFile).string();
  if (!associations && !indexProblem.empty()) {  // missing, or a FIFO, directory, device, loop, unreadable
    std::string name = tum::kIndexFile, path = indexPath_, problem = indexProblem;
    if (problem == "does not exist") {
      name = tum::kAssociationsFile;
      path = (dir / tum::kAssociationsFile).string();
      problem = pathProblem(path);
      if (problem == "does not exist")
        throw Error("sequence " + quoteForMessage(directory) + " has no " + tum::kIndexFile + " (nor " +
                    tum::kAssociationsFile + "): a TUM-layout sequence needs `timestamp depth/file.png` lines in " +
                    tum::kIndexFile);
    }
    throw Error("sequence " + quoteForMessage(directory) + ": " + name + " " + quoteForMessage(path) + " " + problem +
                "; it must be a readable text file of `timestamp depth/file.png` lines");
  }

  // Ground truth: groundtruth.txt, else ICL-NUIM's single *.freiburg file (which also marks the format).
  if (fs::is_regular_file(dir / tum::kGroundTruthFile, ec)) {
    info_.groundTruthPath = (dir / tum::kGroundTruthFile).string();
  } else {
    std::vector<fs::path> freiburg;
    for (const auto& f : fs::directory_iterator(dir, ec))
      if (f.path().extension() == kIclGroundTruthExtension) freiburg.push_back(f.path());
    if (freiburg.size() == 1) info_.groundTruthPath = freiburg.front().string();
  }
  const bool iclNuim = !info_.groundTruthPath.empty() &&
                       fs::path(info_.groundTruthPath).extension() == kIclGroundTruthExtension;

  info_.path = directory;
  std::optional<Calibration> calibration;
  const fs::path calibrationPath = dir / tum::kCalibrationFile;
  if (fs::exists(calibrationPath, ec)) calibration = readCalibration(calibrationPath.string());
  const Calibration* cal = calibration ? &*calibration : nullptr;
  invalidValues_ = invalidDepthValues(cal);

  const bool sevenScenes = cal && std::find(cal->invalidDepthValues.begin(), cal->invalidDepthValues.end(),
                                            uint16_t{65535}) != cal->invalidDepthValues.end();
  const char* detected = sevenScenes ? "7scenes" : (iclNuim ? "icl-nuim" : "tum");
  info_.format = (cal && !cal->format.empty()) ? cal->format : detected;
  resolveCamera(info_, cal, options,
                sevenScenes ? sevenScenesDefaults() : (iclNuim ? iclNuimDefaults() : tumDefaults()));

  std::vector<Entry> all;
  for (const TumIndexEntry& line : readTumIndex(indexPath_, associations)) {
    Entry e;
    e.index = all.size();
    e.line = line.line;
    e.timestamp = line.timestamp;
    e.path = fs::path(line.file).is_absolute() ? line.file : (dir / line.file).string();
    all.push_back(std::move(e));
  }

  if (options.firstFrame >= all.size())
    throw Error("sequence '" + directory + "': first frame " + std::to_string(options.firstFrame) +
                " is past its end (" + std::to_string(all.size()) + " frames)");
  const size_t available = all.size() - options.firstFrame;
  const size_t count = options.maxFrames ? std::min(options.maxFrames, available) : available;
  entries_.assign(
      std::make_move_iterator(all.begin() + static_cast<std::ptrdiff_t>(options.firstFrame)),
      std::make_move_iterator(all.begin() + static_cast<std::ptrdiff_t>(options.firstFrame + count)));
  for (const Entry& e : entries_) {
    const std::string problem = pathProblem(e.path);
    if (problem == "does not exist")
      fail(e, "depth image " + quoteForMessage(e.path) + " does not exist; restore it or remove its line");
    else if (!problem.empty())
      fail(e, "depth image " + quoteForMessage(e.path) + " " + problem + "; it must be a readable PNG file");
  }
  info_.frameCount = entries_.size();

  // Image size: options > calibration > the first frame.
  std::optional<int> width = options.width ? options.width : (cal ? cal->width : std::nullopt);
  std::optional<int> height = options.height ? options.height : (cal ? cal->height : std::nullopt);
  info_.intrinsics.width = 0;  // no size check while probing the first frame
  info_.intrinsics.height = 0;
  if (!width || !height) {
    const DepthFrame first = loadEntry(entries_.front());
    width = width.value_or(first.depth.width());
    height = height.value_or(first.depth.height());
  }
  info_.intrinsics.width = *width;
  info_.intrinsics.height = *height;
  checkIntrinsics(info_, cal, options);
}

void TumReader::fail(const Entry& entry, const std::string& what) const {
  throw Error("sequence '" + info_.path + "', frame " + std::to_string(entry.index) + " (" +
              where(indexPath_, entry.line) + "): " + what);
}

DepthFrame TumReader::loadEntry(const Entry& entry) const {
  DepthFrame frame;
  frame.index = entry.index;
  frame.timestamp = entry.timestamp;
  const int w = info_.intrinsics.width, h = info_.intrinsics.height;
  const auto wrongSize = [&](uint32_t fileW, uint32_t fileH) {
    fail(entry, "depth image '" + entry.path + "' is " + std::to_string(fileW) + "x" + std::to_string(fileH) +
                    (w > 0 ? " but the sequence is " + std::to_string(w) + "x" + std::to_string(h) +
                                 " (calibration.json or the command line)"
                           : " pixels, more than " + std::to_string(kMaxSide) + " per side"));
  };
  // Check the size before decoding, so that a corrupt header cannot ask for a huge allocation.
  if (const auto size = pngSize(entry.path)) {
    const bool expected =
        w > 0 ? (size->first == static_cast<uint32_t>(w) && size->second == static_cast<uint32_t>(h))
              : (size->first <= kMaxSide && size->second <= kMaxSide);
    if (!expected) wrongSize(size->first, size->second);
  }
  try {
    frame.depth = readPng16(entry.path);
  } catch (const Error& e) {
    fail(entry, e.what());
  }
  if (w > 0 && (frame.depth.width() != w || frame.depth.height() != h))
    wrongSize(static_cast<uint32_t>(frame.depth.width()), static_cast<uint32_t>(frame.depth.height()));
  normaliseInvalidDepth(frame.depth, invalidValues_);
  return frame;
}

std::optional<DepthFrame> TumReader::next() {
  if (cursor_ >= entries_.size()) return std::nullopt;
  const Entry& entry = entries_[cursor_++];  // a bad frame is skipped if the caller goes on after the error
  return loadEntry(entry);
}

}  // namespace sb
