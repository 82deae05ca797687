#include "drivers/raw_reader.h"

#include <algorithm>
#include <filesystem>

#include "core/image.h"
#include "core/error.h"
#include "core/input_file.h"
#include "drivers/calibration.h"
#include "drivers/tum_layout.h"

namespace fs = std::filesystem;

namespace sb {

namespace {

// The format stores no timestamps; SLAMBench's recordings are 30 Hz.
constexpr double kRawFrameRateHz = 30.0;
// Largest image side accepted from a header, pixels (guards allocations against corrupt files).
constexpr uint32_t kMaxSide = kMaxDepthImageSide;
constexpr uint64_t kHeaderBytes = 8;  // uint32 width + uint32 height
constexpr uint64_t kRgbChannels = 3;

uint32_t readLe32(const std::uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) |
         (static_cast<uint32_t>(p[2]) << 16) | (static_cast<uint32_t>(p[3]) << 24);
}

void writeLe32(std::ostream& out, uint32_t v) {
  const char b[4] = {static_cast<char>(v & 0xff), static_cast<char>((v >> 8) & 0xff),
                     static_cast<char>((v >> 16) & 0xff), static_cast<char>((v >> 24) & 0xff)};
  out.write(b, sizeof b);
}

// ICL-NUIM's camera, the sequences SLAMBench distributes as .raw files.
CameraDefaults iclNuimDefaults() {
  CameraDefaults d;
  d.name = "ICL-NUIM (fx=481.2, fy=480, cx=319.5, cy=239.5, 1000 units/m)";
  d.intrinsics.fx = 481.2f;
  d.intrinsics.fy = 480.f;
  d.intrinsics.cx = 319.5f;
  d.intrinsics.cy = 239.5f;
  d.depthScale = 1000.0;
  return d;
}

}  // namespace

void appendRawFrame(std::ostream& out, const DepthRaw& depth) {
  const auto w = static_cast<uint32_t>(depth.width()), h = static_cast<uint32_t>(depth.height());
  writeLe32(out, w);
  writeLe32(out, h);
  std::vector<char> bytes(depth.size() * 2);
  for (size_t i = 0; i < depth.size(); ++i) {
    bytes[2 * i] = static_cast<char>(depth.data()[i] & 0xff);
    bytes[2 * i + 1] = static_cast<char>(depth.data()[i] >> 8);
  }
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  writeLe32(out, w);
  writeLe32(out, h);
  const std::vector<char> rgb(depth.size() * kRgbChannels, 0);
  out.write(rgb.data(), static_cast<std::streamsize>(rgb.size()));
}

RawReader::RawReader(const std::string& path, const SequenceOptions& options) {
  info_.path = path;
  info_.format = "raw";
  std::error_code ec;
  const uint64_t fileBytes = fs::file_size(path, ec);
  if (ec) throw Error("cannot read .raw file '" + path + "': " + ec.message());
  openRegularFile(path, ".raw file");  // refuses a FIFO or device before the stream opens (and blocks on) it
  file_.open(path, std::ios::binary);
  if (!file_) throw Error("cannot open .raw file '" + path + "': check that it is readable");

  // Sizes from the first frame's two headers.
  std::uint8_t header[kHeaderBytes];
  if (fileBytes < kHeaderBytes || !file_.read(reinterpret_cast<char*>(header), kHeaderBytes))
    fail(0, "file is empty or shorter than one frame header");
  width_ = readLe32(header);
  height_ = readLe32(header + 4);
  if (width_ == 0 || height_ == 0 || width_ > kMaxSide || height_ > kMaxSide)
    fail(0, "depth header gives " + std::to_string(width_) + "x" + std::to_string(height_) +
                " pixels; this is not a SLAMBench .raw file (or it is corrupt)");
  const uint64_t depthBytes = uint64_t{width_} * height_ * sizeof(uint16_t);
  const uint64_t rgbHeaderAt = kHeaderBytes + depthBytes;
  if (fileBytes < rgbHeaderAt + kHeaderBytes) fail(0, "file ends inside the first frame (truncated)");
  file_.seekg(static_cast<std::streamoff>(rgbHeaderAt));
  if (!file_.read(reinterpret_cast<char*>(header), kHeaderBytes)) fail(0, "cannot read the RGB header");
  rgbWidth_ = readLe32(header);
  rgbHeight_ = readLe32(header + 4);
  if (rgbWidth_ > kMaxSide || rgbHeight_ > kMaxSide)
    fail(0, "RGB header gives " + std::to_string(rgbWidth_) + "x" + std::to_string(rgbHeight_) +
                " pixels; the file is corrupt");
  frameBytes_ = rgbHeaderAt + kHeaderBytes + uint64_t{rgbWidth_} * rgbHeight_ * kRgbChannels;
  if (fileBytes % frameBytes_ != 0)
    throw Error(".raw file '" + path + "' is " + std::to_string(fileBytes) +
                " bytes, not a whole number of " + std::to_string(frameBytes_) + "-byte frames (" +
                std::to_string(width_) + "x" + std::to_string(height_) + " depth): frame " +
                std::to_string(fileBytes / frameBytes_) + " is truncated; re-copy or re-convert the file");
  const auto total = static_cast<size_t>(fileBytes / frameBytes_);

  if (options.width && static_cast<uint32_t>(*options.width) != width_)
    fail(0, "depth is " + std::to_string(width_) + " pixels wide but the command line says " +
                std::to_string(*options.width));
  if (options.height && static_cast<uint32_t>(*options.height) != height_)
    fail(0, "depth is " + std::to_string(height_) + " pixels high but the command line says " +
                std::to_string(*options.height));
  if (options.firstFrame >= total)
    throw Error(".raw file '" + path + "': first frame " + std::to_string(options.firstFrame) +
                " is past its end (" + std::to_string(total) + " frames)");
  first_ = cursor_ = options.firstFrame;
  const size_t available = total - first_;
  end_ = first_ + (options.maxFrames ? std::min(options.maxFrames, available) : available);

  // Calibration: <file>.json, else calibration.json beside it.
  std::optional<Calibration> calibration;
  const fs::path own(path + ".json");
  const fs::path beside = fs::path(path).parent_path() / tum::kCalibrationFile;
  if (fs::is_regular_file(own, ec))
    calibration = readCalibration(own.string());
  else if (fs::is_regular_file(beside, ec))
    calibration = readCalibration(beside.string());
  const Calibration* cal = calibration ? &*calibration : nullptr;
  if (cal && ((cal->width && static_cast<uint32_t>(*cal->width) != width_) ||
              (cal->height && static_cast<uint32_t>(*cal->height) != height_)))
    fail(0, "depth is " + std::to_string(width_) + "x" + std::to_string(height_) + " but '" + cal->path +
                "' gives another size; use the calibration of this recording");
  if (cal && !cal->format.empty()) info_.format = cal->format;
  invalidValues_ = invalidDepthValues(cal);
  resolveCamera(info_, cal, options, iclNuimDefaults());
  info_.intrinsics.width = static_cast<int>(width_);
  info_.intrinsics.height = static_cast<int>(height_);
  checkIntrinsics(info_, cal, options);
  info_.frameCount = end_ - first_;
  buffer_.resize(static_cast<size_t>(depthBytes));
}

void RawReader::fail(size_t frame, const std::string& what) const {
  throw Error(".raw file '" + info_.path + "', frame " + std::to_string(frame) + ": " + what);
}

void RawReader::readHeader(size_t frame, uint64_t offset, const char* what, uint32_t expectW,
                           uint32_t expectH) {
  std::uint8_t header[kHeaderBytes];
  file_.seekg(static_cast<std::streamoff>(offset));
  if (!file_.read(reinterpret_cast<char*>(header), kHeaderBytes))
    fail(frame, std::string("cannot read the ") + what + " header (file truncated since it was opened?)");
  const uint32_t w = readLe32(header), h = readLe32(header + 4);
  if (w != expectW || h != expectH)
    fail(frame, std::string(what) + " header gives " + std::to_string(w) + "x" + std::to_string(h) +
                    " but frame 0 is " + std::to_string(expectW) + "x" + std::to_string(expectH) +
                    "; every frame of a .raw file must have the same size");
}

std::optional<DepthFrame> RawReader::next() {
  if (cursor_ >= end_) return std::nullopt;
  const size_t index = cursor_++;  // a bad frame is skipped if the caller goes on after the error
  const uint64_t offset = frameBytes_ * index;
  readHeader(index, offset + frameBytes_ - uint64_t{rgbWidth_} * rgbHeight_ * kRgbChannels - kHeaderBytes,
             "RGB", rgbWidth_, rgbHeight_);
  readHeader(index, offset, "depth", width_, height_);
  if (!file_.read(reinterpret_cast<char*>(buffer_.data()), static_cast<std::streamsize>(buffer_.size())))
    fail(index, "cannot read the depth pixels (file truncated since it was opened?)");

  DepthFrame frame;
  frame.index = index;
  frame.timestamp = static_cast<double>(index) / kRawFrameRateHz;
  frame.depth = DepthRaw(static_cast<int>(width_), static_cast<int>(height_));
  uint16_t* out = frame.depth.data();
  for (size_t i = 0; i < frame.depth.size(); ++i)
    out[i] = static_cast<uint16_t>(buffer_[2 * i] | (buffer_[2 * i + 1] << 8));
  normaliseInvalidDepth(frame.depth, invalidValues_);
  return frame;
}

}  // namespace sb
