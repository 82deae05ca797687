// The one file of the project that includes OpenNI.h.
#include "drivers/openni2_source.h"

#include <OpenNI.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <thread>
#include <vector>

#include "core/error.h"
#include "drivers/device_clock.h"
#include "drivers/openni2_errors.h"

namespace sb {

namespace {

constexpr int kWaitSliceMs = 100;  // next() looks at stop() and the disconnect flag this often

std::string formatName(openni::PixelFormat f) {
  switch (f) {
    case openni::PIXEL_FORMAT_DEPTH_1_MM: return "1mm";
    case openni::PIXEL_FORMAT_DEPTH_100_UM: return "100um";
    case openni::PIXEL_FORMAT_SHIFT_9_2: return "shift-9.2";
    case openni::PIXEL_FORMAT_SHIFT_9_3: return "shift-9.3";
    default: return "format-" + std::to_string(static_cast<int>(f));
  }
}

std::string modeName(const openni::VideoMode& m) {
  return std::to_string(m.getResolutionX()) + "x" + std::to_string(m.getResolutionY()) + "@" +
         std::to_string(m.getFps()) + " " + formatName(m.getPixelFormat());
}

std::string extendedError() {
  std::string e = openni::OpenNI::getExtendedError();
  while (!e.empty() && (e.back() == '\n' || e.back() == ' ' || e.back() == '\t')) e.pop_back();
  while (!e.empty() && (e.front() == '\n' || e.front() == '\t')) e.erase(e.begin());
  return e.empty() ? "no details from OpenNI2" : e;
}

}  // namespace

const char* cameraStateName(CameraState state) {
  switch (state) {
    case CameraState::streaming: return "streaming";
    case CameraState::lost: return "lost";
    case CameraState::stopped: return "stopped";
  }
  return "unknown";
}

struct OpenNI2Source::Impl : public openni::OpenNI::DeviceDisconnectedListener {
  OpenNI2Options options;
  SequenceInfo info;
  std::unique_ptr<openni::Device> device;
  std::unique_ptr<openni::VideoStream> stream;
  bool convert100um = false;
  DeviceClock clock;
  std::optional<int> lastDeviceIndex;     // of the previous frame on this connection
  double lastFrameHost = 0.0;             // CLOCK_MONOTONIC of the last frame (or of the connection)

  mutable std::mutex mutex;    // guards stats and disconnected_ (the driver's threads call the listener)
  CameraStats stats;
  bool disconnected_ = false;  // the driver reported the open device disconnected

  void onDeviceDisconnected(const openni::DeviceInfo* disconnected) override {
    std::lock_guard lock(mutex);
    if (disconnected && stats.uri == disconnected->getUri()) disconnected_ = true;
  }

  // Opens a device and starts its depth stream; throws sb::Error. `initial`: the first opening (fills info).
  void open(bool initial);
  void close();
  void markLost(const std::string& why);
  DepthFrame copyFrame(const openni::VideoFrameRef& ref) const;
};

namespace {

// Opens the camera `options.uri` (empty: the first one found); sets `uri` to the one opened. Throws sb::Error
// saying what is missing: a camera, its driver, access to it, or a URI among those found.
std::unique_ptr<openni::Device> openDevice(const OpenNI2Options& options, std::string& uri) {
  openni::Array<openni::DeviceInfo> devices;
  openni::OpenNI::enumerateDevices(&devices);
  std::string found;
  for (int i = 0; i < devices.getSize(); ++i)
    found += (found.empty() ? "" : ", ") + std::string("'") + devices[i].getUri() + "' (" + devices[i].getVendor() +
             " " + devices[i].getName() + ")";
  uri = options.uri;
  if (uri.empty()) {
    if (devices.getSize() == 0)
      throw Error(
          "no OpenNI2 depth camera found: plug one in (`lsusb` should list it, e.g. PrimeSense/Asus 1d27:*), "
          "check that its OpenNI2 driver is installed (Debian's libopenni2-0 brings PrimeSense/Asus; other "
          "cameras need their vendor's OpenNI2 driver in the same OpenNI2/Drivers directory); and " +
          cameraAccessHint());
    uri = devices[0].getUri();
  }
  auto dev = std::make_unique<openni::Device>();
  if (dev->open(uri.c_str()) != openni::STATUS_OK) {
    const std::string details = extendedError();
    bool listed = options.uri.empty();
    for (int i = 0; i < devices.getSize() && !listed; ++i) listed = uri == devices[i].getUri();
    if (!listed && classifyOpenFailure(uri, details) == OpenFailure::other)
      throw Error("no OpenNI2 device with URI '" + uri + "' (" + details + "); devices found: " +
                  (found.empty() ? "none" : found) + ". Set the URI to one of them, or leave it empty for the first");
    throw Error(describeOpenFailure(uri, details));
  }
  return dev;
}

// The depth mode of `options` (width, height, fps), in 1 mm units or else 100 um. Throws sb::Error listing
// the modes the camera offers.
openni::VideoMode chooseDepthMode(openni::Device& dev, const std::string& uri, const OpenNI2Options& options) {
  const openni::SensorInfo* sensor = dev.getSensorInfo(openni::SENSOR_DEPTH);
  if (!sensor) throw Error("the OpenNI2 device '" + uri + "' has no depth sensor");
  const auto& modes = sensor->getSupportedVideoModes();
  std::optional<openni::VideoMode> chosen;
  std::string offered;
  for (int i = 0; i < modes.getSize(); ++i) {
    const openni::VideoMode& m = modes[i];
    offered += (offered.empty() ? "" : ", ") + modeName(m);
    if (m.getResolutionX() != options.width || m.getResolutionY() != options.height || m.getFps() != options.fps)
      continue;
    if (m.getPixelFormat() == openni::PIXEL_FORMAT_DEPTH_1_MM) chosen = m;
    if (m.getPixelFormat() == openni::PIXEL_FORMAT_DEPTH_100_UM && !chosen) chosen = m;
  }
  const std::string wanted =
      std::to_string(options.width) + "x" + std::to_string(options.height) + "@" + std::to_string(options.fps);
  if (!chosen)
    throw Error("the OpenNI2 camera '" + uri + "' does not offer the depth mode " + wanted +
                " (1mm or 100um units); it offers: " + (offered.empty() ? "none" : offered) +
                ". Set width, height and fps to one of these");
  return *chosen;
}

// The started depth stream of `dev` in `mode`: registration and mirroring off. Throws sb::Error.
std::unique_ptr<openni::VideoStream> startDepthStream(openni::Device& dev, const std::string& uri,
                                                      const openni::VideoMode& mode) {
  // Registration off before the stream exists (some drivers refuse to change it while streaming).
  if (dev.isImageRegistrationModeSupported(openni::IMAGE_REGISTRATION_OFF) &&
      dev.setImageRegistrationMode(openni::IMAGE_REGISTRATION_OFF) != openni::STATUS_OK)
    spdlog::warn("openni2 '{}': cannot switch depth-to-colour registration off: {}", uri, extendedError());
  auto str = std::make_unique<openni::VideoStream>();
  if (str->create(dev, openni::SENSOR_DEPTH) != openni::STATUS_OK)
    throw Error("cannot create the depth stream of the OpenNI2 camera '" + uri + "': " + extendedError());
  if (str->setVideoMode(mode) != openni::STATUS_OK)
    throw Error("the OpenNI2 camera '" + uri + "' refused the depth mode " + modeName(mode) + ": " +
                extendedError());
  if (str->setMirroringEnabled(false) != openni::STATUS_OK && str->getMirroringEnabled())
    throw Error("the OpenNI2 camera '" + uri + "' streams mirrored depth and refuses to switch mirroring off: " +
                extendedError());
  if (str->start() != openni::STATUS_OK) {
    const std::string details = extendedError();
    str->destroy();
    throw Error(describeOpenFailure(uri, "starting the depth stream failed: " + details));
  }
  return str;
}

// The intrinsics: the configured ones, else from the stream's field of view, the centre at the middle.
// Destroys the stream and throws sb::Error when no focal length is known.
Intrinsics streamIntrinsics(openni::VideoStream& str, const std::string& uri, const OpenNI2Options& options) {
  Intrinsics k;
  k.width = options.width;
  k.height = options.height;
  const float hfov = str.getHorizontalFieldOfView(), vfov = str.getVerticalFieldOfView();
  const bool fovKnown = hfov > 0.f && hfov < 3.1f && vfov > 0.f && vfov < 3.1f;
  if (!fovKnown && (!options.fx || !options.fy))
    spdlog::warn("openni2 '{}' reports no field of view (h {} rad, v {} rad): give fx and fy", uri, hfov, vfov);
  k.fx = options.fx.value_or(fovKnown ? 0.5f * k.width / std::tan(0.5f * hfov) : 0.f);
  k.fy = options.fy.value_or(fovKnown ? 0.5f * k.height / std::tan(0.5f * vfov) : 0.f);
  k.cx = options.cx.value_or(0.5f * k.width);
  k.cy = options.cy.value_or(0.5f * k.height);
  if (!(k.fx > 0.f && k.fy > 0.f)) {
    str.destroy();
    throw Error("no focal length for the OpenNI2 camera '" + uri +
                "': the device reports no field of view; set fx and fy (pixels)");
  }
  return k;
}

}  // namespace

// Plan (the device and its mode), start the stream, read its intrinsics, then take them into use.
void OpenNI2Source::Impl::open(bool initial) {
  std::string uri;
  std::unique_ptr<openni::Device> dev = openDevice(options, uri);
  const openni::VideoMode chosen = chooseDepthMode(*dev, uri, options);
  std::unique_ptr<openni::VideoStream> str = startDepthStream(*dev, uri, chosen);
  const Intrinsics k = streamIntrinsics(*str, uri, options);
  convert100um = chosen.getPixelFormat() == openni::PIXEL_FORMAT_DEPTH_100_UM;

  if (initial) {
    info.path = uri;
    info.format = "openni2";
    info.intrinsics = k;
    info.depthScale = 1000.0;
    info.frameCount = 0;
  } else if (std::abs(k.fx - info.intrinsics.fx) > 0.5f || std::abs(k.fy - info.intrinsics.fy) > 0.5f) {
    spdlog::warn("openni2: the reopened camera '{}' reports other intrinsics (fx {:.1f}, fy {:.1f}) than at start "
                 "(fx {:.1f}, fy {:.1f}); the start values stay in use",
                 uri, k.fx, k.fy, info.intrinsics.fx, info.intrinsics.fy);
  }

  device = std::move(dev);
  stream = std::move(str);
  clock.reset();
  lastDeviceIndex.reset();
  lastFrameHost = DeviceClock::monotonicNow();
  std::lock_guard lock(mutex);
  disconnected_ = false;
  stats.uri = uri;
  stats.mode = modeName(chosen) + (convert100um ? "->1mm" : "");
  stats.state = CameraState::streaming;
  stats.lastError.clear();
  stats.attempts = 0;
}

void OpenNI2Source::Impl::close() {
  // Stop, destroy the stream, then close the device: the order every OpenNI2 driver supports.
  if (stream) {
    stream->stop();
    stream->destroy();
    stream.reset();
  }
  if (device) {
    device->close();
    device.reset();
  }
}

void OpenNI2Source::Impl::markLost(const std::string& why) {
  {
    std::lock_guard lock(mutex);
    stats.state = CameraState::lost;
    stats.lastError = why;
    ++stats.disconnects;
  }
  spdlog::warn("openni2: camera lost: {}", why);
  close();
}

DepthFrame OpenNI2Source::Impl::copyFrame(const openni::VideoFrameRef& ref) const {
  if (ref.getWidth() != info.intrinsics.width || ref.getHeight() != info.intrinsics.height)
    throw Error("the OpenNI2 camera '" + stats.uri + "' sent a " + std::to_string(ref.getWidth()) + "x" +
                std::to_string(ref.getHeight()) + " depth frame in the " + std::to_string(info.intrinsics.width) +
                "x" + std::to_string(info.intrinsics.height) + " mode (cropping set by another program?)");
  DepthFrame f;
  f.depth.resize(ref.getWidth(), ref.getHeight());
  const auto* bytes = static_cast<const uint8_t*>(ref.getData());
  const int stride = ref.getStrideInBytes();
  for (int y = 0; y < ref.getHeight(); ++y) {
    const auto* row = reinterpret_cast<const uint16_t*>(bytes + static_cast<size_t>(y) * stride);
    uint16_t* out = f.depth.data() + static_cast<size_t>(y) * f.depth.width();
    if (convert100um) {
      for (int x = 0; x < ref.getWidth(); ++x) out[x] = row[x] == 0xFFFF ? 0 : static_cast<uint16_t>((row[x] + 5u) / 10u);
    } else {
      for (int x = 0; x < ref.getWidth(); ++x) out[x] = row[x] == 0xFFFF ? 0 : row[x];
    }
  }
  return f;
}

OpenNI2Source::OpenNI2Source(const OpenNI2Options& options) : impl_(std::make_unique<Impl>()) {
  if (options.width <= 0 || options.height <= 0 || options.fps <= 0)
    throw Error("openni2: width, height and fps must be positive (got " + std::to_string(options.width) + "x" +
                std::to_string(options.height) + "@" + std::to_string(options.fps) + ")");
  if (!(options.frameTimeoutSeconds > 0) || !(options.reconnectMinSeconds > 0) ||
      options.reconnectMaxSeconds < options.reconnectMinSeconds)
    throw Error("openni2: need frame timeout > 0 and 0 < reconnect min <= reconnect max (seconds)");
  impl_->options = options;
  if (openni::OpenNI::initialize() != openni::STATUS_OK) {
    const std::string details = extendedError();
    openni::OpenNI::shutdown();
    throw Error("OpenNI2 did not start: " + details +
                ". Install the camera drivers (Debian: libopenni2-0; they live in the OpenNI2/Drivers directory "
                "beside libOpenNI2.so) and check [Drivers] Repository in /etc/openni2/OpenNI.ini");
  }
  openni::OpenNI::addDeviceDisconnectedListener(impl_.get());
  try {
    impl_->open(true);
  } catch (...) {
    impl_->close();
    openni::OpenNI::removeDeviceDisconnectedListener(impl_.get());
    openni::OpenNI::shutdown();
    throw;
  }
  spdlog::info("openni2: '{}' streaming {} (fx {:.1f}, fy {:.1f}, cx {:.1f}, cy {:.1f})", impl_->stats.uri,
               impl_->stats.mode, impl_->info.intrinsics.fx, impl_->info.intrinsics.fy, impl_->info.intrinsics.cx,
               impl_->info.intrinsics.cy);
}

OpenNI2Source::~OpenNI2Source() {
  impl_->close();
  openni::OpenNI::removeDeviceDisconnectedListener(impl_.get());
  openni::OpenNI::shutdown();
}

const SequenceInfo& OpenNI2Source::info() const { return impl_->info; }

CameraStats OpenNI2Source::stats() const {
  std::lock_guard lock(impl_->mutex);
  CameraStats s = impl_->stats;
  if (stopRequested_.load()) s.state = CameraState::stopped;
  return s;
}

std::optional<DepthFrame> OpenNI2Source::next() {
  Impl& m = *impl_;
  double backoff = m.options.reconnectMinSeconds;
  std::optional<double> retryAt;  // CLOCK_MONOTONIC of the next reopening attempt while lost
  while (!stopRequested_.load()) {
    const double now = DeviceClock::monotonicNow();
    if (!m.stream) {  // lost: reopen with backoff
      if (!retryAt) retryAt = now + backoff;
      if (now < *retryAt) {
        std::this_thread::sleep_for(std::chrono::duration<double>(std::min(*retryAt - now, kWaitSliceMs * 1e-3)));
        continue;
      }
      try {
        m.open(false);
        std::lock_guard lock(m.mutex);
        ++m.stats.reconnects;
        spdlog::info("openni2: camera '{}' reopened ({} {}), streaming again", m.stats.uri, m.stats.mode,
                     m.stats.reconnects == 1 ? "first reconnect" : std::to_string(m.stats.reconnects) + " reconnects");
      } catch (const Error& e) {
        m.close();
        {
          std::lock_guard lock(m.mutex);
          ++m.stats.attempts;
          m.stats.lastError = e.what();
        }
        spdlog::debug("openni2: reopening failed (next try in {:.1f} s): {}", backoff, e.what());
        backoff = std::min(2 * backoff, m.options.reconnectMaxSeconds);
        retryAt = DeviceClock::monotonicNow() + backoff;
      }
      continue;
    }

    bool disconnected;
    {
      std::lock_guard lock(m.mutex);
      disconnected = m.disconnected_;
    }
    std::string lostWhy;
    if (disconnected) {
      lostWhy = "the driver reports '" + m.stats.uri + "' disconnected";
    } else if (now - m.lastFrameHost > m.options.frameTimeoutSeconds) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.1f s", m.options.frameTimeoutSeconds);
      lostWhy = "no frame from '" + m.stats.uri + "' for " + buf;
    }
    if (!lostWhy.empty()) {
      m.markLost(lostWhy);
      if (!m.options.reconnect) throw Error("the OpenNI2 camera was lost: " + lostWhy);
      backoff = m.options.reconnectMinSeconds;
      retryAt.reset();
      continue;
    }

    openni::VideoStream* streams[] = {m.stream.get()};
    int ready = -1;
    if (openni::OpenNI::waitForAnyStream(streams, 1, &ready, kWaitSliceMs) != openni::STATUS_OK) continue;
    openni::VideoFrameRef ref;
    if (m.stream->readFrame(&ref) != openni::STATUS_OK || !ref.isValid()) continue;
    const double arrival = DeviceClock::monotonicNow();
    m.lastFrameHost = arrival;
    DepthFrame f = m.copyFrame(ref);
    f.timestamp = m.clock.map(ref.getTimestamp(), arrival);
    std::lock_guard lock(m.mutex);
    const int deviceIndex = ref.getFrameIndex();
    if (m.lastDeviceIndex && deviceIndex > *m.lastDeviceIndex + 1)
      m.stats.drops += static_cast<uint64_t>(deviceIndex - *m.lastDeviceIndex - 1);
    m.lastDeviceIndex = deviceIndex;
    f.index = m.stats.frames++;
    return f;
  }
  m.close();
  return std::nullopt;
}

}  // namespace sb
